#pragma once
// JSON CSG models: a tree of primitives, formulas and operators, read into
// one expression of the field core. The schema is documented with examples
// in README.md ("Model files"); examples/models/ holds working models.
//
//   { "name": "...", "dimension": 2 | 3, "rfunction": "r0",
//     "bounds": { "min": [...], "max": [...] },
//     "field": NODE }
//
//   NODE = { "primitive": TYPE, "name": ..., parameters }
//        | { "formula": "x^2 + y^2 - 1", "inside": "negative", "name": ... }
//        | { "op": "union" | "intersection" | "difference" | "complement"
//                | "normalize", "args": [NODE...], "rfunction": ... }
//        | { "op": "trim", "entity": NODE, "region": NODE,
//            "method": "smooth", "orthogonalize": false }
//        | { "ref": "name of an earlier named node" }
//
// Every error throws ModelError, whose message names the file, the place
// (line:column for malformed JSON, a JSON pointer such as
// /field/args/2/radius for a bad node) and what is wrong.

#include <sage/geometry/model.hpp>

#include <optional>
#include <string>

namespace sage::geometry {

struct ModelOptions {
  /// Replaces the model's default R-function (nodes with their own
  /// "rfunction" keep it).
  std::optional<RSystem> rfunction;
};

/// Reads a model file. Throws ModelError.
Model read_model(const std::string& path, const ModelOptions& options = {});
/// Parses model text; `source` names it in messages. Throws ModelError.
Model parse_model(const std::string& text, const std::string& source, const ModelOptions& options = {});

}  // namespace sage::geometry
