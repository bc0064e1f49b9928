#include <sage/problems/problem_file.hpp>

#include <sage/expression/formula.hpp>
#include <sage/geometry/cad_model.hpp>
#include <sage/geometry/csg_model.hpp>
#include <sage/geometry/json_fields.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace sage::problems {

namespace {

using geometry::Json;

class Reader : geometry::JsonFields<ProblemError> {
 public:
  Reader(std::string path, ProblemFile& out, geometry::LoadOptions domain_options)
      : JsonFields<ProblemError>(path), path_(std::move(path)), out_(out), domain_options_(std::move(domain_options)) {}

  void read(const Json& top) {
    if (!top.is_object()) fail("", "a problem file is a JSON object");
    std::string physics = "poisson";
    if (top.contains("physics")) {
      if (!top["physics"].is_string()) fail("/physics", "expected \"poisson\" or \"elasticity\"");
      physics = top["physics"].get<std::string>();
      if (physics != "poisson" && physics != "elasticity")
        fail("/physics", "unknown physics \"" + physics + "\" (use \"poisson\" or \"elasticity\")");
    }
    if (physics == "elasticity") {
      allow_keys(top, "",
                 {"name", "description", "physics", "domain", "deflection", "bounds", "E", "nu", "plane", "body_force",
                  "boundary", "exact"});
    } else {
      allow_keys(top, "",
                 {"name", "description", "physics", "domain", "deflection", "bounds", "conductivity", "source",
                  "boundary", "exact", "robin"});
    }
    if (!top.contains("domain")) fail("", "missing \"domain\" (an inline CSG model or the path of a model file)");
    if (top.contains("deflection") && !domain_options_.deflection) {
      const double deflection = number(top["deflection"], "/deflection");
      if (!(deflection > 0))
        fail("/deflection", "expected a positive length (the CAD tessellation's chordal deflection)");
      domain_options_.deflection = deflection;
      out_.deflection = deflection;
    }
    read_domain(top["domain"]);
    if (top.contains("deflection") && out_.model.faces.empty())
      fail("/deflection", "applies to CAD domains (STEP, IGES, BREP files) only");
    domain_.dimension = out_.model.dimension;
    domain_.field = out_.model.field;
    if (out_.model.field_follows_surface) domain_.boundary_mesh = out_.model.surface;
    read_bounds(top);
    if (physics == "elasticity")
      out_.physics = read_elasticity(top);
    else
      out_.physics = read_poisson(top);
  }

 private:
  solver::PoissonProblem read_poisson(const Json& top) {
    solver::PoissonProblem p;
    p.domain = domain_;
    if (top.contains("conductivity")) p.conductivity = formula(top["conductivity"], "/conductivity");
    if (top.contains("source")) p.source = formula(top["source"], "/source");
    if (top.contains("exact")) {
      p.exact = formula(top["exact"], "/exact");
      out_.exact_formula = top["exact"].is_string() ? top["exact"].get<std::string>() : top["exact"].dump();
    }
    if (top.contains("boundary")) read_boundary(top["boundary"], p);
    if (top.contains("robin")) {
      if (!top["robin"].is_string()) fail("/robin", "expected \"weak\" or \"structure\"");
      try {
        out_.robin = solver::parse_robin_route(top["robin"].get<std::string>());
      } catch (const std::invalid_argument& e) {
        fail("/robin", e.what());
      }
    }
    return p;
  }

  Expr formula(const Json& value, const std::string& pointer) const {
    if (value.is_number()) return Expr(number(value, pointer));
    if (!value.is_string()) fail(pointer, "expected a formula (string) or a number");
    try {
      return parse_formula(value.get<std::string>(), out_.model.dimension);
    } catch (const FormulaError& e) {
      fail(pointer, std::string("bad formula: ") + e.what());
    } catch (const std::invalid_argument& e) {
      fail(pointer, std::string("bad formula: ") + e.what());
    }
  }

  void read_domain(const Json& domain) {
    if (domain.is_string()) {
      std::filesystem::path model_path(domain.get<std::string>());
      if (model_path.is_relative()) model_path = std::filesystem::path(path_).parent_path() / model_path;
      out_.model = geometry::load_model(model_path.string(), domain_options_);
    } else if (domain.is_object()) {
      out_.model = geometry::parse_model(domain.dump(), path_ + " (/domain)");
    } else {
      fail("/domain", "expected an inline CSG model (object) or the path of a model file (string)");
    }
  }

  void read_bounds(const Json& top) {
    const int d = domain_.dimension;
    if (top.contains("bounds")) {
      const Json& b = top["bounds"];
      if (!b.is_object() || !b.contains("min") || !b.contains("max"))
        fail("/bounds", "expected { \"min\": [...], \"max\": [...] }");
      for (const char* key : {"min", "max"}) {
        const Json& v = b[key];
        (key[1] == 'i' ? domain_.min : domain_.max) = point(v, std::string("/bounds/") + key, d);
      }
    } else if (out_.model.bounds) {
      for (int a = 0; a < d; ++a) {
        domain_.min[a] = out_.model.bounds->min[a];
        domain_.max[a] = out_.model.bounds->max[a];
      }
    } else {
      fail("/bounds", "the domain model has no bounds: give \"bounds\": { \"min\": [...], \"max\": [...] }");
    }
    for (int a = 0; a < d; ++a)
      if (!(domain_.max[a] > domain_.min[a])) fail("/bounds", "max must exceed min on every axis");
  }

  /// A vector of dimension-many formulas or numbers.
  std::array<Expr, 3> vector(const Json& value, const std::string& pointer) const {
    const int d = out_.model.dimension;
    if (!value.is_array() || static_cast<int>(value.size()) != d)
      fail(pointer, "expected " + std::to_string(d) + " formulas or numbers, one per axis");
    std::array<Expr, 3> v{Expr(0.0), Expr(0.0), Expr(0.0)};
    for (int a = 0; a < d; ++a)
      v[static_cast<std::size_t>(a)] = formula(value[static_cast<std::size_t>(a)], pointer + "/" + std::to_string(a));
    return v;
  }

  solver::ElasticityProblem read_elasticity(const Json& top) {
    solver::ElasticityProblem e;
    e.domain = domain_;
    e.material.young = number_at(top, "E", "");
    if (!(e.material.young >= solver::kSmallestModulus && e.material.young <= solver::kLargestDatum))
      fail("/E",
           "Young's modulus E must be positive, within 1e-100 and 1e100 (change the units), not " + top["E"].dump());
    e.material.poisson = number_at(top, "nu", "");
    if (!(e.material.poisson > -1.0 && e.material.poisson < 0.5))
      fail("/nu", "Poisson's ratio nu must lie in (-1, 0.5), not " + top["nu"].dump());
    if (top.contains("plane")) {
      if (e.domain.dimension != 2) fail("/plane", "\"plane\" (stress or strain) applies to 2D problems only");
      if (!top["plane"].is_string()) fail("/plane", "expected \"stress\" or \"strain\"");
      try {
        e.material.plane = solver::parse_plane_mode(top["plane"].get<std::string>());
      } catch (const std::invalid_argument& error) {
        fail("/plane", error.what());
      }
    }
    if (top.contains("body_force")) e.body_force = vector(top["body_force"], "/body_force");
    if (top.contains("exact")) {
      e.exact = vector(top["exact"], "/exact");
      out_.exact_formula = top["exact"].dump();
    }
    if (top.contains("boundary")) {
      const Json& boundary = top["boundary"];
      if (!boundary.is_object()) fail("/boundary", "expected an object mapping part names to conditions");
      for (const auto& [name, condition] : boundary.items()) {
        const std::string pointer = "/boundary/" + name;
        solver::ElasticPart part = read_elastic_part(condition, pointer, name);
        if (name == "default") {
          if (condition.contains("selector")) fail(pointer + "/selector", "the default part takes no selector");
          e.rest = part;
          continue;
        }
        part.selector = selector(condition, pointer, name);
        e.parts.push_back(part);
      }
    }
    return e;
  }

  solver::ElasticPart read_elastic_part(const Json& c, const std::string& pointer, const std::string& name) const {
    if (!c.is_object()) fail(pointer, "expected an object with \"displacement\", \"traction\" or \"pressure\"");
    allow_keys(c, pointer, {"displacement", "traction", "pressure", "selector", "faces"});
    solver::ElasticPart part;
    part.name = name;
    if (c.contains("displacement")) {
      const Json& u = c["displacement"];
      const std::string at = pointer + "/displacement";
      if (!u.is_object() || u.empty())
        fail(at, "expected the fixed components, e.g. {\"x\": 0, \"y\": 0} (a roller gives one)");
      for (const auto& [axis, value] : u.items()) {
        const auto position = std::string("xyz").find(axis);
        if (axis.size() != 1 || position == std::string::npos || static_cast<int>(position) >= out_.model.dimension)
          fail(at + "/" + axis,
               "unknown component \"" + axis + "\" (use " + (out_.model.dimension == 2 ? "x, y" : "x, y, z") + ")");
        part.displacement[position] = formula(value, at + "/" + axis);
      }
    }
    if (c.contains("traction")) part.traction = vector(c["traction"], pointer + "/traction");
    if (c.contains("pressure")) part.pressure = formula(c["pressure"], pointer + "/pressure");
    part.loaded = c.contains("traction") || c.contains("pressure");
    if (part.fixed() && part.loaded)
      fail(pointer,
           "a part is either fixed (\"displacement\") or loaded (\"traction\", \"pressure\"), not both: "
           "split it into two parts (a roller's free components are traction-free)");
    if (c.contains("traction") && c.contains("pressure")) fail(pointer, "give \"traction\" or \"pressure\", not both");
    return part;
  }

  /// The CAD faces a part names: "faces": [3, 4] or "faces": "cylinder
  /// radius 4" (a query, or a face name from the file), or its own name:
  /// "face:12", or the name the file gives faces. Empty when it names none.
  std::vector<std::size_t> named_faces(const Json& condition, const std::string& pointer,
                                       const std::string& name) const {
    const std::string at = pointer + "/faces";
    try {
      if (condition.contains("faces")) {
        const Json& faces = condition["faces"];
        if (faces.is_string()) return geometry::faces_matching(out_.model, faces.get<std::string>());
        if (!faces.is_array() || faces.empty())
          fail(at, "expected face numbers ([3, 4, 9]) or a face query (\"cylinder radius 4\") as sage info lists them");
        std::vector<std::size_t> out;
        for (std::size_t i = 0; i < faces.size(); ++i) {
          if (!faces[i].is_number_integer() || faces[i].get<long long>() < 1)
            fail(at + "/" + std::to_string(i), "expected a face number (from 1)");
          out.push_back(faces[i].get<std::size_t>());
        }
        return out;
      }
      if (name.rfind("face:", 0) == 0) {
        const std::string number = name.substr(5);
        if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos)
          fail(pointer, "\"face:N\" names one face by its number (from 1), as sage info lists it");
        return {std::stoul(number)};
      }
      std::vector<std::size_t> named;  // faces the CAD file gives this part's name
      for (std::size_t f = 0; f < out_.model.faces.size(); ++f)
        if (out_.model.faces[f].name == name) named.push_back(f + 1);
      return named;
    } catch (const std::invalid_argument& e) {
      fail(condition.contains("faces") ? at : pointer, e.what());
    } catch (const std::out_of_range&) {
      fail(pointer, "face number out of range");
    }
    return {};
  }

  /// A named part's selector: its own "selector" formula, its faces, or the model's part of that name.
  Expr selector(const Json& condition, const std::string& pointer, const std::string& name) const {
    if (condition.contains("selector") && condition.contains("faces"))
      fail(pointer, "give \"selector\" or \"faces\", not both");
    if (condition.contains("selector")) return formula(condition["selector"], pointer + "/selector");
    const std::vector<std::size_t> faces = named_faces(condition, pointer, name);
    if (!faces.empty()) {
      try {
        return geometry::faces_selector(out_.model, faces);
      } catch (const std::invalid_argument& e) {
        fail(condition.contains("faces") ? pointer + "/faces" : pointer, e.what());
      }
    }
    const auto named = out_.model.named.find(name);
    if (named == out_.model.named.end()) {
      std::string known;
      for (const auto& [n, e] : out_.model.named) known += (known.empty() ? "" : ", ") + n;
      fail(pointer, "unknown boundary part '" + name + "': the model names " +
                        (known.empty() ? std::string("no parts") : known) +
                        " (or give a \"selector\" formula that vanishes on the part)");
    }
    return named->second;
  }

  solver::BoundaryPart read_condition(const Json& c, const std::string& pointer, const std::string& name) const {
    if (!c.is_object()) fail(pointer, "expected an object with \"type\"");
    allow_keys(c, pointer, {"type", "value", "flux", "beta", "selector", "faces"});
    if (!c.contains("type") || !c["type"].is_string()) fail(pointer, "missing \"type\": dirichlet, neumann or robin");
    solver::BoundaryPart part;
    part.name = name;
    const std::string type = c["type"].get<std::string>();
    auto allow_only = [&](std::set<std::string> keys) {
      keys.insert("type");
      keys.insert("selector");
      keys.insert("faces");
      allow_keys(c, pointer, keys);
    };
    if (type == "dirichlet") {
      allow_only({"value"});
      part.kind = solver::BoundaryKind::Dirichlet;
      if (c.contains("value")) part.value = formula(c["value"], pointer + "/value");
    } else if (type == "neumann") {
      allow_only({"flux"});
      part.kind = solver::BoundaryKind::Neumann;
      if (c.contains("flux")) part.flux = formula(c["flux"], pointer + "/flux");
    } else if (type == "robin") {
      allow_only({"flux", "beta"});
      part.kind = solver::BoundaryKind::Robin;
      if (!c.contains("beta")) fail(pointer, "a robin condition needs \"beta\"");
      part.beta = formula(c["beta"], pointer + "/beta");
      if (c.contains("flux")) part.flux = formula(c["flux"], pointer + "/flux");
    } else {
      fail(pointer + "/type", "unknown type '" + type + "' (use dirichlet, neumann or robin)");
    }
    return part;
  }

  void read_boundary(const Json& boundary, solver::PoissonProblem& p) const {
    if (!boundary.is_object()) fail("/boundary", "expected an object mapping part names to conditions");
    p.rest_given = boundary.contains("default");
    for (const auto& [name, condition] : boundary.items()) {
      const std::string pointer = "/boundary/" + name;
      solver::BoundaryPart part = read_condition(condition, pointer, name);
      if (name == "default") {
        if (condition.contains("selector") || condition.contains("faces"))
          fail(pointer, "the default part takes no selector or faces: it is the boundary no other part claims");
        p.rest = part;
        continue;
      }
      part.selector = selector(condition, pointer, name);
      p.parts.push_back(part);
    }
  }

  std::string path_;
  ProblemFile& out_;
  geometry::LoadOptions domain_options_;  // for a domain read from a file
  solver::ProblemDomain domain_;          // from the model and "bounds", given to the physics
};

}  // namespace

ProblemFile read_problem_file(const std::string& path, const geometry::LoadOptions& domain_options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ProblemError(path + ": cannot open the problem file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  Json top;
  try {
    top = Json::parse(text);
  } catch (const Json::exception& e) {
    // nlohmann's message names the line and column; drop its "[json.exception...] " tag.
    const std::string what = e.what();
    const auto tag = what.find("] ");
    throw ProblemError(path + ": malformed JSON: " + (tag == std::string::npos ? what : what.substr(tag + 2)));
  }
  ProblemFile out;
  Reader(path, out, domain_options).read(top);
  return out;
}

}  // namespace sage::problems
