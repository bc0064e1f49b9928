#pragma once
// The bodies of the fuzz targets, shared by the libFuzzer programs
// (libfuzzer_main.cpp, one per target) and the plain regression driver
// (regressions.cpp) that replays saved inputs in the ordinary build.
//
// Each body takes one input, runs it through a reader (and what follows
// it) and returns. An exception derived from std::exception is an accepted
// answer to bad input and is caught; anything else (a crash, a sanitizer
// report, another exception, a hang, huge memory) is a finding.

#include <sage/expression/expression.hpp>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <string>

namespace sage::fuzz {

void model(const std::uint8_t* data, std::size_t size);    // model.cpp: parse_model
void problem(const std::uint8_t* data, std::size_t size);  // problem.cpp: read_problem_file
void formula(const std::uint8_t* data, std::size_t size);  // formula.cpp: parse_formula, tape, evaluation
void mesh(const std::uint8_t* data, std::size_t size);     // mesh.cpp: load_mesh (OFF, STL, OBJ, PLY)
void geojson(const std::uint8_t* data, std::size_t size);  // geojson.cpp: load_model through GDAL
void solve(const std::uint8_t* data, std::size_t size);    // solve.cpp: read_problem_file, then a tiny solve

// ---- shared support (fuzz_support.cpp) ------------------------------------

/// This process's scratch folder, /tmp/sage-fuzz-PID (made on first use,
/// removed at exit), with problems/ for the input and models/ holding
/// copies of examples/models, so that the bundled problem files' relative
/// domains ("../models/plate_with_holes.json") resolve.
const std::filesystem::path& scratch();

/// Writes the input to scratch()/name and returns its path.
std::string write_scratch(const std::string& name, const std::uint8_t* data, std::size_t size);

/// Once per process: one OpenMP thread, and GDAL held to the JSON vector
/// drivers with every HTTP request refused (a fuzzed file must not reach
/// the network or open other files through a VRT).
void setup();

/// False when the problem file's "domain" is a path that leaves scratch()
/// (absolute, or too many ".."): such inputs are skipped.
bool domain_stays_in_scratch(const std::string& text);

/// False when the environment sets SAGE_FUZZ_KNOWN_BUGS: the bodies then
/// run the inputs of open bugs that they otherwise skip (see each body),
/// to check a fix against fuzz/regressions.
bool skip_known_bugs();

/// A body's catch: prints what the input was rejected for when the
/// environment sets SAGE_FUZZ_VERBOSE (to see what a seed or reproducer
/// does), else nothing.
void rejected(const std::exception& error);

/// Compiles `field` to a tape and evaluates it at a few fixed points
/// (doubles) and over a box (intervals).
void evaluate(const Expr& field, int dimension);

}  // namespace sage::fuzz
