#include <sage/expression/blend.hpp>
#include <sage/expression/bounded.hpp>
#include <sage/expression/formula.hpp>
#include <sage/expression/normalize.hpp>
#include <sage/expression/primitives.hpp>
#include <sage/expression/trimming.hpp>
#include <sage/geometry/csg_model.hpp>
#include <sage/geometry/json_fields.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

namespace sage::geometry {

namespace {

std::string line_and_column(const std::string& text, std::size_t byte) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

/// Reads nodes, keeping the file name and the JSON pointer for messages.
class Reader : JsonFields<ModelError> {
 public:
  Reader(Model& model, const ModelOptions& options)
      : JsonFields<ModelError>(model.source), model_(model), options_(options) {}

  void read_top(const Json& top) {
    if (!top.is_object()) fail("", "a model must be a JSON object");
    allow_keys(top, "", {"name", "dimension", "rfunction", "bounds", "field", "description", "sage"});
    if (top.contains("name")) model_.name = string_at(top, "name", "");
    if (!top.contains("dimension")) fail("", "missing \"dimension\" (2 or 3)");
    const double d = number_at(top, "dimension", "");
    if (d != 2 && d != 3) fail("/dimension", "must be 2 or 3");
    model_.dimension = static_cast<int>(d);
    model_.rfunction = options_.rfunction          ? *options_.rfunction
                       : top.contains("rfunction") ? rsystem(string_at(top, "rfunction", ""), "/rfunction")
                                                   : RSystem::r0();
    if (top.contains("bounds")) model_.bounds = bounds(top["bounds"], "/bounds");
    if (!top.contains("field")) fail("", "missing \"field\" (the root node)");
    model_.field = node(top["field"], "/field");
  }

 private:
  // ---- small typed accessors (the rest in json_fields.hpp) -----------------
  double positive_at(const Json& j, const char* key, const std::string& at) const {
    const double v = number_at(j, key, at);
    if (!(v > 0)) fail(at + "/" + key, "must be positive");
    return v;
  }
  Vec3 vector_at(const Json& j, const char* key, const std::string& at, int n) const {
    if (!j.contains(key)) fail(at, std::string("missing parameter \"") + key + "\"");
    return point(j[key], at + "/" + key, n);
  }
  RSystem rsystem(const std::string& text, const std::string& at) const {
    try {
      return RSystem::parse(text);
    } catch (const std::invalid_argument& e) {
      fail(at, e.what());
    }
  }
  Bounds bounds(const Json& j, const std::string& at) const {
    if (!j.is_object()) fail(at, "expected {\"min\": [...], \"max\": [...]}");
    allow_keys(j, at, {"min", "max"});
    Bounds b{vector_at(j, "min", at, model_.dimension), vector_at(j, "max", at, model_.dimension)};
    for (int i = 0; i < model_.dimension; ++i)
      if (!(b.max[i] > b.min[i])) fail(at, "max must exceed min in every coordinate");
    return b;
  }

  // ---- nodes ----------------------------------------------------------------
  Expr node(const Json& j, const std::string& at) {
    // A depth limit keeps hostile input from overflowing the stack.
    if (++depth_ > kMaxDepth) fail(at, "nodes nested more than " + std::to_string(kMaxDepth) + " levels deep");
    Expr e = node_body(j, at);
    --depth_;
    return e;
  }

  Expr node_body(const Json& j, const std::string& at) {
    if (!j.is_object()) fail(at, "a node must be a JSON object");
    Expr e;
    if (j.contains("primitive"))
      e = primitive(j, at);
    else if (j.contains("formula"))
      e = formula(j, at);
    else if (j.contains("op"))
      e = operation(j, at);
    else if (j.contains("ref"))
      e = reference(j, at);
    else
      fail(at, "a node needs one of \"primitive\", \"formula\", \"op\" or \"ref\"");
    if (j.contains("name")) {
      const std::string name = string_at(j, "name", at);
      if (model_.named.count(name)) fail(at + "/name", "the name \"" + name + "\" is used twice");
      model_.named.emplace(name, e);
    }
    return e;
  }

  RSystem node_rsystem(const Json& j, const std::string& at) const {
    return j.contains("rfunction") ? rsystem(string_at(j, "rfunction", at), at + "/rfunction") : model_.rfunction;
  }

  Expr primitive(const Json& j, const std::string& at) {
    const std::string type = string_at(j, "primitive", at);
    const int dim = model_.dimension;
    auto need_3d = [&] {
      if (dim != 3) fail(at + "/primitive", "\"" + type + "\" is a 3D primitive but the model is 2D");
    };
    auto keys = [&](std::initializer_list<const char*> k) {
      std::vector<const char*> all{"primitive", "name"};
      all.insert(all.end(), k);
      const std::set<std::string> allowed(all.begin(), all.end());
      for (const auto& [key, value] : j.items())
        if (!allowed.count(key))
          fail(at + "/" + key, "unknown parameter \"" + key + "\" for primitive \"" + type + "\"");
    };
    model_.primitives.push_back({j.contains("name") ? string_at(j, "name", at) : "", type, at});
    try {
      if (type == "halfplane" || type == "halfspace") {
        keys({"point", "normal"});
        return halfspace(vector_at(j, "point", at, dim), vector_at(j, "normal", at, dim), dim);
      }
      if (type == "disk" || type == "ball") {
        keys({"center", "radius"});
        return ball(vector_at(j, "center", at, dim), positive_at(j, "radius", at), dim);
      }
      if (type == "ellipse" || type == "ellipsoid") {
        keys({"center", "semi_axes"});
        return ellipsoid(vector_at(j, "center", at, dim), vector_at(j, "semi_axes", at, dim), dim);
      }
      if (type == "box" || type == "rectangle") {
        keys({"min", "max", "rfunction"});
        return box(vector_at(j, "min", at, dim), vector_at(j, "max", at, dim), dim, node_rsystem(j, at));
      }
      if (type == "cylinder") {
        need_3d();
        keys({"point", "axis", "radius"});
        return cylinder(vector_at(j, "point", at, 3), vector_at(j, "axis", at, 3), positive_at(j, "radius", at));
      }
      if (type == "capped_cylinder") {
        need_3d();
        keys({"base", "axis", "radius", "height", "rfunction"});
        return capped_cylinder(vector_at(j, "base", at, 3), vector_at(j, "axis", at, 3), positive_at(j, "radius", at),
                               positive_at(j, "height", at), node_rsystem(j, at));
      }
      if (type == "cone") {
        need_3d();
        keys({"apex", "axis", "half_angle_degrees"});
        return cone(vector_at(j, "apex", at, 3), vector_at(j, "axis", at, 3),
                    number_at(j, "half_angle_degrees", at) * M_PI / 180.0);
      }
      if (type == "torus") {
        need_3d();
        keys({"center", "axis", "major_radius", "minor_radius"});
        return torus(vector_at(j, "center", at, 3), vector_at(j, "axis", at, 3), positive_at(j, "major_radius", at),
                     positive_at(j, "minor_radius", at));
      }
    } catch (const std::invalid_argument& e) {
      fail(at, std::string("primitive \"") + type + "\": " + e.what());
    }
    fail(at + "/primitive",
         "unknown primitive \"" + type +
             "\" (known: halfplane, halfspace, disk, ball, ellipse, ellipsoid, box, rectangle, cylinder, "
             "capped_cylinder, cone, torus)");
  }

  Expr formula(const Json& j, const std::string& at) {
    allow_keys(j, at, {"formula", "inside", "name"});
    const std::string text = string_at(j, "formula", at);
    model_.primitives.push_back({j.contains("name") ? string_at(j, "name", at) : "", "formula", at});
    Expr e;
    try {
      e = parse_formula(text, model_.dimension);
    } catch (const FormulaError& err) {
      fail(at + "/formula", "in \"" + text + "\": " + err.what());
    }
    const std::string inside = j.contains("inside") ? string_at(j, "inside", at) : "positive";
    if (inside == "negative") return -e;
    if (inside != "positive") fail(at + "/inside", "must be \"positive\" or \"negative\"");
    return e;
  }

  std::vector<Expr> arguments(const Json& j, const std::string& at, std::size_t min_count, std::size_t max_count) {
    if (!j.contains("args") || !j["args"].is_array()) fail(at, "missing \"args\" (an array of nodes)");
    const Json& args = j["args"];
    if (args.size() < min_count || args.size() > max_count) {
      const std::string range = min_count == max_count ? std::to_string(min_count)
                                : max_count == SIZE_MAX
                                    ? "at least " + std::to_string(min_count)
                                    : std::to_string(min_count) + " to " + std::to_string(max_count);
      fail(at + "/args",
           "expected " + range + " argument" + (max_count == 1 ? "" : "s") + ", found " + std::to_string(args.size()));
    }
    std::vector<Expr> out;
    for (std::size_t i = 0; i < args.size(); ++i) out.push_back(node(args[i], at + "/args/" + std::to_string(i)));
    return out;
  }

  Expr operation(const Json& j, const std::string& at) {
    const std::string op = string_at(j, "op", at);
    if (op == "trim") return trim(j, at);
    if (op.rfind("bounded", 0) == 0 || op == "iso_surface") return bounded(j, at, op);
    if (j.contains("blend")) return blended(j, at, op);
    allow_keys(j, at, {"op", "args", "rfunction", "name"});
    const RSystem s = node_rsystem(j, at);
    if (op == "union") return r_disjunction_n(arguments(j, at, 1, SIZE_MAX), s);
    if (op == "intersection") return r_conjunction_n(arguments(j, at, 1, SIZE_MAX), s);
    if (op == "difference") {
      // a AND NOT b1 AND NOT b2 ...: the subtrahends united first.
      std::vector<Expr> args = arguments(j, at, 2, SIZE_MAX);
      std::vector<Expr> removed(args.begin() + 1, args.end());
      return r_and(args[0], -r_disjunction_n(removed, s), s);
    }
    if (op == "complement") return -arguments(j, at, 1, 1)[0];
    if (op == "normalize") return normalize(arguments(j, at, 1, 1)[0], model_.dimension);
    fail(at + "/op", "unknown operator \"" + op +
                         "\" (known: union, intersection, difference, complement, normalize, trim, bounded, "
                         "bounded_union, bounded_intersection, bounded_difference, iso_surface)");
  }

  // Soft blending (paper 000): "blend": {"function": 1..6, "amount": n};
  // n-ary operators fold from the left.
  Expr blended(const Json& j, const std::string& at, const std::string& op) {
    allow_keys(j, at, {"op", "args", "blend", "name"});
    const Json& b = j["blend"];
    const std::string here = at + "/blend";
    if (!b.is_object()) fail(here, "expected {\"function\": 1..6, \"amount\": n}");
    allow_keys(b, here, {"function", "amount"});
    BlendFunction fb{};
    try {
      const double number = number_at(b, "function", here);
      // Checked before the cast: a number beyond int's range does not convert.
      if (number != std::floor(number) || number < 1 || number > 6)
        fail(here + "/function", "must be an integer 1 to 6");
      fb = blend_function_from_number(static_cast<int>(number));
    } catch (const std::invalid_argument& e) {
      fail(here + "/function", e.what());
    }
    const double n = number_at(b, "amount", here);
    if (n < 0) fail(here + "/amount", "must be >= 0");
    Expr (*combine)(const Expr&, const Expr&, BlendFunction, double) = nullptr;
    if (op == "union") combine = blend_union;
    if (op == "intersection") combine = blend_intersection;
    if (op == "difference") combine = blend_difference;
    if (!combine) fail(here, "only union, intersection and difference can blend");
    const std::vector<Expr> args = arguments(j, at, 2, SIZE_MAX);
    Expr e = args[0];
    for (std::size_t i = 1; i < args.size(); ++i) e = combine(e, args[i], fb, n);
    return e;
  }

  // Bounded potentials and their composition (paper 001).
  Expr bounded(const Json& j, const std::string& at, const std::string& op) {
    try {
      if (op == "bounded") {
        allow_keys(j, at, {"op", "args", "width", "name"});
        return bounded_potential(arguments(j, at, 1, 1)[0], positive_at(j, "width", at));
      }
      if (op == "iso_surface") {
        allow_keys(j, at, {"op", "args", "iso", "name"});
        return iso_field(arguments(j, at, 1, 1)[0], j.contains("iso") ? number_at(j, "iso", at) : 0.5);
      }
      allow_keys(j, at, {"op", "args", "theta1_degrees", "theta2_degrees", "iso", "profile_points", "sharp", "name"});
      BoundedOp kind = BoundedOp::Union;
      if (op == "bounded_intersection")
        kind = BoundedOp::Intersection;
      else if (op == "bounded_difference")
        kind = BoundedOp::Difference;
      else if (op != "bounded_union")
        fail(at + "/op", "unknown operator \"" + op + "\"");
      BoundedTransition tr;
      if (j.contains("theta1_degrees")) tr.theta1 = number_at(j, "theta1_degrees", at) * M_PI / 180;
      if (j.contains("theta2_degrees")) tr.theta2 = number_at(j, "theta2_degrees", at) * M_PI / 180;
      if (j.contains("iso")) tr.iso = number_at(j, "iso", at);
      if (j.contains("sharp")) {
        if (!j["sharp"].is_boolean()) fail(at + "/sharp", "expected true or false");
        tr.sharp = j["sharp"].get<bool>();
      }
      if (j.contains("profile_points")) {
        const Json& pts = j["profile_points"];
        if (!pts.is_array()) fail(at + "/profile_points", "expected an array of points");
        for (std::size_t i = 0; i < pts.size(); ++i)
          tr.profile_points.push_back(point(pts[i], at + "/profile_points/" + std::to_string(i), model_.dimension));
      }
      const std::vector<Expr> args = arguments(j, at, 2, 2);
      return bounded_compose(kind, args[0], args[1], tr, model_.dimension);
    } catch (const std::invalid_argument& e) {
      fail(at, e.what());
    }
  }

  Expr trim(const Json& j, const std::string& at) {
    allow_keys(j, at, {"op", "entity", "region", "method", "orthogonalize", "rfunction", "name"});
    if (!j.contains("entity")) fail(at, "missing \"entity\" (the node whose zero set is trimmed)");
    if (!j.contains("region")) fail(at, "missing \"region\" (the node >= 0 on the kept part)");
    const Expr h = node(j["entity"], at + "/entity");
    Expr t = node(j["region"], at + "/region");
    TrimMethod method = TrimMethod::Smooth;
    if (j.contains("method")) {
      try {
        method = parse_trim_method(string_at(j, "method", at));
      } catch (const std::invalid_argument& e) {
        fail(at + "/method", e.what());
      }
    }
    if (j.contains("rfunction") && method != TrimMethod::Simple)
      fail(at + "/rfunction", "only \"method\": \"simple\" trimming uses an R-function");
    if (j.contains("orthogonalize")) {
      if (!j["orthogonalize"].is_boolean()) fail(at + "/orthogonalize", "expected true or false");
      if (j["orthogonalize"].get<bool>()) t = orthogonalize(h, t, model_.dimension);
    }
    switch (method) {
      case TrimMethod::Simple: return trim_simple(h, t, node_rsystem(j, at));
      case TrimMethod::Normalized: return trim_normalized(h, t);
      case TrimMethod::Smooth: return trim_smooth(h, t);
    }
    return trim_smooth(h, t);
  }

  Expr reference(const Json& j, const std::string& at) {
    allow_keys(j, at, {"ref"});
    const std::string name = string_at(j, "ref", at);
    const auto it = model_.named.find(name);
    if (it == model_.named.end()) fail(at + "/ref", "no node named \"" + name + "\" before this point");
    return it->second;
  }

  // Deep enough for any hand-written or generated CSG tree, shallow enough
  // for sanitizer builds, whose stack frames are several times larger.
  static constexpr int kMaxDepth = 256;
  Model& model_;
  const ModelOptions& options_;
  int depth_ = 0;
};

}  // namespace

Model parse_model(const std::string& text, const std::string& source, const ModelOptions& options) {
  Model model;
  model.source = source;
  Json top;
  try {
    top = Json::parse(text);
  } catch (const Json::parse_error& e) {
    // e.what() repeats the position in bytes; keep only its description.
    std::string what = e.what();
    const auto colon = what.rfind(": ");
    throw ModelError(source + ": " + line_and_column(text, e.byte > 0 ? e.byte - 1 : 0) +
                     ": malformed JSON: " + (colon == std::string::npos ? what : what.substr(colon + 2)));
  } catch (const Json::out_of_range& e) {
    // A number too large for a double ("1e999"): the message quotes it.
    const std::string what = e.what();
    const auto open = what.find('\''), close = what.rfind('\'');
    const std::string token = open < close ? what.substr(open + 1, close - open - 1) : "";
    const auto at = token.empty() ? std::string::npos : text.find(token);
    throw ModelError(source + ": " + (at == std::string::npos ? "" : line_and_column(text, at) + ": ") +
                     "number is not finite (overflows a double): " + token);
  }
  Reader(model, options).read_top(top);
  return model;
}

Model read_model(const std::string& path, const ModelOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelError(path + ": cannot open the model file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw ModelError(path + ": cannot read the model file");
  return parse_model(text.str(), path, options);
}

}  // namespace sage::geometry
