// The faces of a CAD model as boundary parts: their listing for
// `sage info`, queries by surface type and parameters, and selectors.
// Needs no OpenCASCADE: it reads what load_cad left in the Model.
#include <sage/geometry/cad_model.hpp>

#include "mesh_internal.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace sage::geometry {

bool is_cad_path(const std::string& path) {
  const std::string ext = lowercase_extension(path);
  return ext == ".step" || ext == ".stp" || ext == ".iges" || ext == ".igs" || ext == ".brep";
}

namespace {

/// Components below `zero` print as 0 (a direction's -0 and 1e-17
/// leftovers, a centroid's rounding about the origin).
std::string vec(const std::array<double, 3>& v, double zero = 1e-12) {
  auto clean = [zero](double x) { return std::abs(x) <= zero ? 0.0 : x; };
  std::ostringstream s;
  s << "(" << clean(v[0]) << ", " << clean(v[1]) << ", " << clean(v[2]) << ")";
  return s.str();
}

void check_face(const Model& model, std::size_t face) {
  if (model.faces.empty())
    throw std::invalid_argument("the model has no faces to name (faces come with CAD files: STEP, IGES, BREP)");
  if (face < 1 || face > model.faces.size())
    throw std::invalid_argument("face " + std::to_string(face) + ": the model has faces 1.." +
                                std::to_string(model.faces.size()) + " (sage info lists them)");
}

/// The model's size: the diagonal of its triangles' bounding box.
double model_size(const Model& model) {
  std::array<double, 3> lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const auto& p : model.surface->points)
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], p[i]);
      hi[i] = std::max(hi[i], p[i]);
    }
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

/// One condition of a face query: "radius 4", "axis 0 0 1", ...
struct Condition {
  std::string key;
  std::vector<double> values;
  std::string text;
  std::string colour;  // "colour #rrggbb", in lower case
};

bool is_colour(const std::string& key) { return key == "colour" || key == "color"; }

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::vector<std::string> words(const std::string& query) {
  std::istringstream in(query);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

double number(const std::string& word, const std::string& query) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(word, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != word.size() || !std::isfinite(v))
    throw std::invalid_argument("face query '" + query + "': '" + word + "' is not a number");
  return v;
}

bool same_direction(const std::array<double, 3>& a, const std::vector<double>& b, bool either_sense) {
  const double nb = std::hypot(b[0], b[1], b[2]);
  if (!(nb > 0)) return false;
  const double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / nb;
  return (either_sense ? std::abs(c) : c) > 1 - 5e-13;  // within 1e-6 radians
}

bool meets(const ModelFace& f, const Condition& c, double length_tolerance) {
  auto close = [&](double a, double b) { return std::abs(a - b) <= length_tolerance; };
  if (is_colour(c.key)) return f.colour == c.colour;
  if (c.key == "radius") return f.radius && close(*f.radius, c.values[0]);
  if (c.key == "normal") return f.normal && same_direction(*f.normal, c.values, false);
  if (c.key == "axis") return f.axis && same_direction(*f.axis, c.values, true);
  if (c.key == "center")
    return f.center && close(f.center->at(0), c.values[0]) && close(f.center->at(1), c.values[1]) &&
           close(f.center->at(2), c.values[2]);
  return false;
}

/// What the faces of `type` have for a condition's key, for the message
/// when nothing matched.
std::string values_present(const Model& model, const std::string& type, const std::string& key) {
  std::set<std::string> seen;
  for (const ModelFace& f : model.faces) {
    if (type != "any" && f.surface != type) continue;
    std::ostringstream s;
    if (is_colour(key)) s << f.colour;
    if (key == "radius" && f.radius) s << *f.radius;
    if (key == "normal" && f.normal) s << vec(*f.normal);
    if (key == "axis" && f.axis) s << vec(*f.axis);
    if (key == "center" && f.center) s << vec(*f.center);
    if (!s.str().empty()) seen.insert(s.str());
  }
  if (seen.empty()) return "none of them has a " + key;
  std::string out = "their " + key + (seen.size() > 1 ? "s: " : ": ");
  std::size_t n = 0;
  for (const std::string& v : seen) {
    if (n++ == 12) {
      out += ", ...";
      break;
    }
    out += (n > 1 ? ", " : "") + v;
  }
  return out;
}

const std::set<std::string>& surface_types() {
  static const std::set<std::string> types = {"plane",  "cylinder",   "cone",      "sphere", "torus", "bspline",
                                              "bezier", "revolution", "extrusion", "offset", "other", "any"};
  return types;
}

}  // namespace

std::string describe_face(const Model& model, std::size_t face) {
  check_face(model, face);
  const ModelFace& f = model.faces[face - 1];
  const double zero = 1e-12 * model_size(model);
  auto at = [zero](const std::array<double, 3>& p) { return vec(p, zero); };
  std::ostringstream s;
  s << face << "  " << f.surface;
  if (!f.name.empty()) s << " \"" << f.name << "\"";
  if (!f.colour.empty()) s << "  colour " << f.colour;
  if (f.normal) s << "  normal " << vec(*f.normal);
  if (f.surface == "sphere" && f.radius) s << "  radius " << *f.radius << ", centre " << at(*f.center);
  if (f.surface == "torus" && f.radius)
    s << "  radii " << *f.radius << " and " << *f.minor_radius << ", axis " << vec(*f.axis) << " through "
      << at(*f.center);
  if (f.surface == "cylinder" && f.radius)
    s << "  radius " << *f.radius << ", axis " << vec(*f.axis) << " through " << at(*f.center);
  if (f.surface == "cone" && f.radius)
    s << "  half-angle " << *f.half_angle << " degrees, radius " << *f.radius << " at " << at(*f.center) << ", axis "
      << vec(*f.axis);
  s << "  area " << f.area << "  centroid " << at(f.centroid);
  return s.str();
}

std::vector<std::size_t> faces_matching(const Model& model, const std::string& query) {
  check_face(model, 1);
  std::vector<std::size_t> named;
  for (std::size_t i = 0; i < model.faces.size(); ++i)
    if (!model.faces[i].name.empty() && model.faces[i].name == query) named.push_back(i + 1);
  if (!named.empty()) return named;

  const std::vector<std::string> w = words(query);
  if (w.empty() || !surface_types().count(w[0]))
    throw std::invalid_argument("face query '" + query +
                                "': start with a surface type (plane, cylinder, cone, sphere, torus, bspline, ..., "
                                "or any), or give a face name from the file");
  const std::string type = w[0];
  std::vector<Condition> conditions;
  for (std::size_t i = 1; i < w.size();) {
    Condition c{w[i], {}, w[i], {}};
    if (is_colour(c.key)) {
      const std::string colour = i + 1 < w.size() ? lower(w[i + 1]) : "";
      if (colour.size() != 7 || colour[0] != '#' ||
          !std::all_of(colour.begin() + 1, colour.end(), [](unsigned char x) { return std::isxdigit(x); }))
        throw std::invalid_argument("face query '" + query + "': '" + c.key + "' needs a colour as #rrggbb");
      c.colour = colour;
      c.text += " " + colour;
      conditions.push_back(c);
      i += 2;
      continue;
    }
    const std::size_t arity = c.key == "radius"                                             ? 1
                              : (c.key == "normal" || c.key == "axis" || c.key == "center") ? 3
                                                                                            : 0;
    if (arity == 0)
      throw std::invalid_argument("face query '" + query + "': unknown condition '" + c.key +
                                  "' (use radius R, normal X Y Z, axis X Y Z, center X Y Z or colour #rrggbb)");
    if (i + arity >= w.size())
      throw std::invalid_argument("face query '" + query + "': '" + c.key + "' needs " + std::to_string(arity) +
                                  (arity == 1 ? " number" : " numbers"));
    for (std::size_t k = 1; k <= arity; ++k) {
      c.values.push_back(number(w[i + k], query));
      c.text += " " + w[i + k];
    }
    conditions.push_back(c);
    i += arity + 1;
  }
  const double tolerance = 1e-6 * model_size(model);
  std::vector<std::size_t> out;
  std::size_t of_type = 0;
  for (std::size_t i = 0; i < model.faces.size(); ++i) {
    const ModelFace& f = model.faces[i];
    if (type != "any" && f.surface != type) continue;
    ++of_type;
    if (std::all_of(conditions.begin(), conditions.end(), [&](const Condition& c) { return meets(f, c, tolerance); }))
      out.push_back(i + 1);
  }
  if (!out.empty()) return out;
  if (of_type == 0) throw std::invalid_argument("face query '" + query + "': the model has no " + type + " face");
  // Name the first condition no face of the type meets, with the values they have.
  for (const Condition& c : conditions) {
    bool any = false;
    for (const ModelFace& f : model.faces)
      any = any || ((type == "any" || f.surface == type) && meets(f, c, tolerance));
    if (!any)
      throw std::invalid_argument("face query '" + query + "': no " + (type == "any" ? "face" : type) + " has " +
                                  c.text + " (" + values_present(model, type, c.key) + ")");
  }
  throw std::invalid_argument("face query '" + query + "': no single face meets all its conditions");
}

Expr faces_selector(const Model& model, const std::vector<std::size_t>& faces) {
  if (faces.empty()) throw std::invalid_argument("no face given");
  for (std::size_t f : faces) check_face(model, f);
  const std::set<std::size_t> wanted(faces.begin(), faces.end());
  std::vector<mesh::Point> points;
  points.reserve(model.surface->points.size());
  for (const auto& p : model.surface->points) points.emplace_back(p[0], p[1], p[2]);
  std::vector<mesh::Triangle> triangles;
  for (std::size_t t = 0; t < model.surface->triangles.size(); ++t)
    if (wanted.count(model.triangle_faces[t])) {
      const auto& tri = model.surface->triangles[t];
      triangles.push_back({tri[0], tri[1], tri[2]});
    }
  if (!std::all_of(faces.begin(), faces.end(), [&](std::size_t f) { return model.faces[f - 1].exact_surface; }))
    return mesh::brep_distance(points, triangles, RSystem::r0(), RSystem::r0(), false);

  // Exact faces: the surface's own field, as a CSG model's named primitive,
  // so that the solver's boundary points (on the exact surface) find their
  // part within its selector tolerance. Where a surface also carries faces
  // not selected, it is zero only near the selected faces' triangles
  // (within twice the deflection).
  std::map<const void*, std::vector<std::size_t>> selected_on, all_on;  // by surface
  for (std::size_t f = 1; f <= model.faces.size(); ++f) {
    const void* surface = model.faces[f - 1].exact_surface->id();
    all_on[surface].push_back(f);
    if (wanted.count(f)) selected_on[surface].push_back(f);
  }
  std::vector<Expr> terms;
  for (const auto& [surface, on] : selected_on) {
    const Expr& field = *model.faces[on.front() - 1].exact_surface;
    if (on.size() == all_on[surface].size()) {
      terms.push_back(field);
      continue;
    }
    std::vector<mesh::Triangle> own;
    for (std::size_t t = 0; t < model.surface->triangles.size(); ++t)
      if (std::count(on.begin(), on.end(), model.triangle_faces[t])) {
        const auto& tri = model.surface->triangles[t];
        own.push_back({tri[0], tri[1], tri[2]});
      }
    const Expr near = mesh::brep_distance(points, own, RSystem::r0(), RSystem::r0(), false) - 2 * model.deflection;
    terms.push_back(max(abs(field), near));
  }
  if (terms.size() == 1) return terms.front();
  Expr selector = abs(terms.front());
  for (std::size_t i = 1; i < terms.size(); ++i) selector = min(selector, abs(terms[i]));
  return selector;
}

}  // namespace sage::geometry
