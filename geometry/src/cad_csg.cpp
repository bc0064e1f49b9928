// exact_csg: a CAD solid bounded by planes, cylinders, cones, spheres and
// tori as a Boolean formula over the normalized primitives of those
// surfaces, so that the field and the solver's cut cells follow the exact
// faces instead of their tessellation. Boundary-to-CSG conversion after
// Shapiro and Vossler ("Separation for boundary to CSG conversion", ACM
// TOG 12, 1993), with the cells of the surfaces' arrangement found by
// sampling:
//  1. one literal per distinct surface, built once and shared by every
//     term that uses it (the solver's cut-cell quadrature then meets each
//     surface once, boolean_form.hpp);
//  2. points on a jittered grid and on both sides of every face, each
//     classified against the exact solid (BRepClass3d) and by its
//     literals' signs;
//  3. a sign vector seen both inside and outside (a fillet's cylinder, say,
//     that is material by the fillet and air far from it) needs separating
//     halfspaces: the planes of the curved faces' bounding boxes are added;
//  4. the inside vectors are covered by prime implicants (sign_cover.hpp);
//  5. the formula is checked before use: its sign at fresh points against
//     the classifier, zero at the tessellation's nodes (which lie on the
//     exact faces), and nonzero at points of its surfaces inside the solid
//     (where touching terms would vanish).
// Anything unsupported or failing returns why; load_cad then keeps the
// tessellated field.
#include "mesh_internal.hpp"  // CGAL's headers before OCCT's (OCCT's Handle macro)

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include "cad_internal.hpp"
#include "sign_cover.hpp"

#include <sage/expression/primitives.hpp>
#include <sage/tape/evaluator.hpp>

#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <Bnd_Box.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <gp_Cone.hxx>
#include <gp_Cylinder.hxx>
#include <gp_Pln.hxx>
#include <gp_Sphere.hxx>
#include <gp_Torus.hxx>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <sstream>

namespace sage::geometry::cad {

namespace {

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 minus(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// A surface that bounds the solid or separates its cells: its normalized
/// primitive (> 0 on one side) and what identifies it among the others.
struct Literal {
  std::string kind;  // plane, cylinder, cone, sphere, torus
  Vec3 origin{}, axis{};
  double radius = 0, minor = 0, angle = 0;
  std::size_t face = 0;    // the first face on it (from 1); 0 for separators
  bool separator = false;  // a bounding plane of a curved face
  Expr field;

  bool same_surface(const Literal& o, double length) const {
    if (kind != o.kind) return false;
    const bool parallel = norm(cross(axis, o.axis)) < 1e-9;
    const Vec3 d = minus(o.origin, origin);
    if (kind == "plane") return parallel && std::abs(dot(axis, d)) < length;
    if (kind == "sphere") return norm(d) < length && std::abs(radius - o.radius) < length;
    if (kind == "cylinder") return parallel && norm(cross(axis, d)) < length && std::abs(radius - o.radius) < length;
    // Cones share apex, axis sense and angle; tori centre, axis and radii.
    const bool same_axis = kind == "cone" ? dot(axis, o.axis) > 0 : true;
    return parallel && same_axis && norm(d) < length && std::abs(radius - o.radius) < length &&
           std::abs(minor - o.minor) < length && std::abs(angle - o.angle) < 1e-9;
  }
};

Vec3 point(const gp_Pnt& p, double scale) { return {p.X() / scale, p.Y() / scale, p.Z() / scale}; }
Vec3 direction(const gp_Dir& d) { return {d.X(), d.Y(), d.Z()}; }

/// The literal of face `index`'s surface, or why there is none.
std::optional<Literal> literal_of(const TopoDS_Face& face, std::size_t index, double scale, std::string& why_not) {
  const BRepAdaptor_Surface surface(face);
  Literal l;
  l.face = index;
  switch (surface.GetType()) {
    case GeomAbs_Plane: {
      const gp_Pln p = surface.Plane();
      l.kind = "plane", l.origin = point(p.Location(), scale), l.axis = direction(p.Axis().Direction());
      l.field = halfspace(l.origin, l.axis, 3);
      return l;
    }
    case GeomAbs_Cylinder: {
      const gp_Cylinder c = surface.Cylinder();
      l.kind = "cylinder", l.origin = point(c.Location(), scale), l.axis = direction(c.Axis().Direction());
      l.radius = c.Radius() / scale;
      l.field = cylinder(l.origin, l.axis, l.radius);
      return l;
    }
    case GeomAbs_Sphere: {
      const gp_Sphere s = surface.Sphere();
      l.kind = "sphere", l.origin = point(s.Location(), scale), l.radius = s.Radius() / scale;
      l.field = ball(l.origin, l.radius, 3);
      return l;
    }
    case GeomAbs_Cone: {
      // OCCT's conical surface has both nappes; the primitive has one, the face's.
      const gp_Cone c = surface.Cone();
      l.kind = "cone", l.origin = point(c.Apex(), scale), l.axis = direction(c.Axis().Direction());
      const double u = 0.5 * (surface.FirstUParameter() + surface.LastUParameter());
      const double v = 0.5 * (surface.FirstVParameter() + surface.LastVParameter());
      if (dot(minus(point(surface.Value(u, v), scale), l.origin), l.axis) < 0)
        for (double& a : l.axis) a = -a;
      l.angle = std::abs(c.SemiAngle());
      l.field = cone(l.origin, l.axis, l.angle);
      return l;
    }
    case GeomAbs_Torus: {
      const gp_Torus t = surface.Torus();
      if (t.MajorRadius() <= t.MinorRadius()) {
        why_not = "face " + std::to_string(index) + " is a self-intersecting torus";
        return std::nullopt;
      }
      l.kind = "torus", l.origin = point(t.Location(), scale), l.axis = direction(t.Axis().Direction());
      l.radius = t.MajorRadius() / scale, l.minor = t.MinorRadius() / scale;
      l.field = torus(l.origin, l.axis, l.radius, l.minor);
      return l;
    }
    default: break;
  }
  why_not = "face " + std::to_string(index) + " is not a plane, cylinder, cone, sphere or torus (" +
            describe_surface(face, scale).surface + ")";
  return std::nullopt;
}

/// Adds `l` unless a literal on the same surface is there already; its index.
std::size_t add_distinct(std::vector<Literal>& literals, Literal l, double length) {
  for (std::size_t k = 0; k < literals.size(); ++k)
    if (literals[k].same_surface(l, length)) return k;
  literals.push_back(std::move(l));
  return literals.size() - 1;
}

/// The six planes of a curved face's bounding box.
void add_separators(std::vector<Literal>& literals, const TopoDS_Face& face, double scale, double length) {
  Bnd_Box box;
  BRepBndLib::AddOptimal(face, box, false, false);
  double lo[3], hi[3];
  box.Get(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  for (int a = 0; a < 3; ++a)
    for (double c : {lo[a], hi[a]}) {
      Literal l;
      l.kind = "plane", l.separator = true;
      l.origin = {0, 0, 0}, l.origin[static_cast<std::size_t>(a)] = c / scale;
      l.axis = {0, 0, 0}, l.axis[static_cast<std::size_t>(a)] = 1;
      l.field = halfspace(l.origin, l.axis, 3);
      add_distinct(literals, std::move(l), length);
    }
}

/// Distance to the tessellation (CGAL's AABB tree).
class TessellationDistance {
 public:
  explicit TessellationDistance(const TriangleSurface& surface) {
    const auto at = [&](std::uint32_t i) {
      return mesh::Point(surface.points[i][0], surface.points[i][1], surface.points[i][2]);
    };
    for (const auto& t : surface.triangles) triangles_.emplace_back(at(t[0]), at(t[1]), at(t[2]));
    tree_.insert(triangles_.begin(), triangles_.end());
    tree_.accelerate_distance_queries();
  }
  double operator()(const Vec3& p) const { return std::sqrt(tree_.squared_distance(mesh::Point(p[0], p[1], p[2]))); }

 private:
  using Triangles = std::vector<mesh::Kernel::Triangle_3>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<mesh::Kernel, CGAL::AABB_triangle_primitive<mesh::Kernel, Triangles::iterator>>>;
  Triangles triangles_;
  Tree tree_;
};

/// Membership in the exact solid: +1 inside, -1 outside, 0 on it (within
/// `tolerance` mm). Farther than `margin` from the tessellation (which lies
/// within its deflection of the faces), CGAL's exact point membership in
/// the triangles answers; OpenCASCADE's classifier, many times slower,
/// answers nearer.
class Membership {
 public:
  Membership(const TopoDS_Shape& shape, double scale, double tolerance, const TriangleSurface& tessellation,
             double margin)
      : classifier_(shape), scale_(scale), tolerance_(tolerance), margin_(margin), distance_(tessellation) {
    std::vector<mesh::Point> points;
    for (const auto& p : tessellation.points) points.emplace_back(p[0], p[1], p[2]);
    std::vector<mesh::Triangle> triangles;
    for (const auto& t : tessellation.triangles) triangles.push_back({t[0], t[1], t[2]});
    mesh_ = mesh::make_mesh_classifier(points, triangles);
  }

  /// Whether `p` is surely not on the solid's boundary.
  bool off_boundary(const Vec3& p) const { return distance_(p) > margin_; }

  int operator()(const Vec3& p) {
    if (off_boundary(p)) return static_cast<int>(mesh_->classify(p.data()));
    classifier_.Perform(gp_Pnt(p[0] * scale_, p[1] * scale_, p[2] * scale_), tolerance_);
    switch (classifier_.State()) {
      case TopAbs_IN: return 1;
      case TopAbs_OUT: return -1;
      default: return 0;
    }
  }

 private:
  BRepClass3d_SolidClassifier classifier_;
  double scale_, tolerance_, margin_;
  TessellationDistance distance_;
  std::shared_ptr<const PointClassifier> mesh_;
};

/// The literals' signs at a point; empty where one is too close to zero
/// to tell.
class SignsAt {
 public:
  SignsAt(const std::vector<Literal>& literals, double zero) : zero_(zero), count_(literals.size()) {
    std::vector<Expr> roots;
    for (const Literal& l : literals) roots.push_back(l.field);
    tape_ = std::make_unique<Tape>(roots, 3);
    eval_ = std::make_unique<Evaluator<double>>(*tape_);
  }

  SignVector operator()(const Vec3& p) {
    eval_->evaluate(p.data());
    SignVector v((count_ + 63) / 64, 0);
    for (std::size_t l = 0; l < count_; ++l) {
      const double value = eval_->result(l);
      if (std::abs(value) <= zero_) return {};
      if (value > 0) v[l / 64] |= std::uint64_t{1} << (l % 64);
    }
    return v;
  }

 private:
  double zero_;
  std::size_t count_;
  std::unique_ptr<Tape> tape_;
  std::unique_ptr<Evaluator<double>> eval_;
};

struct Sample {
  Vec3 p;
  int side;  // +1 inside, -1 outside
};

/// Points of a jittered n^3 grid over the box and on both sides of every
/// triangle (at `offsets` along its normal), classified; points on the
/// solid's boundary are left out.
std::vector<Sample> samples(const Vec3& lo, const Vec3& hi, int n, const TriangleSurface& surface,
                            const std::vector<double>& offsets, std::uint32_t seed, Membership& membership) {
  std::vector<Vec3> points;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const int index[3] = {i, j, k};
        Vec3 p;
        for (int a = 0; a < 3; ++a)
          p[static_cast<std::size_t>(a)] = lo[static_cast<std::size_t>(a)] +
                                           (hi[static_cast<std::size_t>(a)] - lo[static_cast<std::size_t>(a)]) *
                                               (index[a] + unit(random)) / n;
        points.push_back(p);
      }
  for (const auto& t : surface.triangles) {
    const Vec3 &a = surface.points[t[0]], &b = surface.points[t[1]], &c = surface.points[t[2]];
    Vec3 normal = cross(minus(b, a), minus(c, a));
    const double length = norm(normal);
    if (length == 0) continue;
    for (double& x : normal) x /= length;
    const Vec3 centroid{(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3};
    for (double offset : offsets)
      for (double sense : {-1.0, 1.0})
        points.push_back({centroid[0] + sense * offset * normal[0], centroid[1] + sense * offset * normal[1],
                          centroid[2] + sense * offset * normal[2]});
  }
  std::vector<Sample> out;
  for (const Vec3& p : points)
    if (const int side = membership(p)) out.push_back({p, side});
  return out;
}

std::string at(const Vec3& p) {
  std::ostringstream s;
  s << "(" << p[0] << ", " << p[1] << ", " << p[2] << ")";
  return s.str();
}

/// Sorts samples into the inside and outside sign vectors; a vector seen
/// on both sides is returned in `conflict` (its first point).
void sign_vectors(const std::vector<Sample>& points, SignsAt& signs, std::vector<SignVector>& inside,
                  std::vector<SignVector>& outside, std::optional<Vec3>& conflict) {
  std::map<SignVector, std::pair<int, Vec3>> seen;
  conflict.reset();
  for (const Sample& s : points) {
    SignVector v = signs(s.p);
    if (v.empty()) continue;
    const auto [it, fresh] = seen.emplace(std::move(v), std::make_pair(s.side, s.p));
    if (!fresh && it->second.first != s.side && !conflict) conflict = s.p;
  }
  inside.clear(), outside.clear();
  for (const auto& [v, side] : seen) (side.first > 0 ? inside : outside).push_back(v);
}

/// A term's literals: (literal, sign) pairs.
using Conjunction = std::vector<std::pair<std::size_t, bool>>;

/// The R-function of a union of conjunctions, factored: a literal common
/// to all terms is taken out (s AND (A OR B) for (s AND A) OR (s AND B)),
/// and terms are grouped by the literal most of them share. Where two
/// terms end on the same face (the wall and the base of an L on the
/// bottom plane), the unfactored R-disjunction of two vanishing terms
/// would have a gradient of 2 + sqrt(2), not 1, on that face.
Expr factored(std::vector<Conjunction> terms, const std::vector<Expr>& positive, const std::vector<Expr>& negative,
              const RSystem& system) {
  const auto literal = [&](const std::pair<std::size_t, bool>& l) {
    return l.second ? positive[l.first] : negative[l.first];
  };
  std::map<std::pair<std::size_t, bool>, std::size_t> count;
  for (const Conjunction& t : terms)
    for (const auto& l : t) ++count[l];
  std::pair<std::size_t, bool> most{0, false};
  std::size_t most_count = 0;
  for (const auto& [l, n] : count)
    if (n > most_count) most = l, most_count = n;
  if (terms.size() == 1 || most_count == terms.size()) {
    // Literals in every term, AND the rest.
    std::vector<Expr> conjuncts;
    Conjunction common;
    for (const auto& [l, n] : count)
      if (n == terms.size()) common.push_back(l), conjuncts.push_back(literal(l));
    std::vector<Conjunction> rest;
    bool rest_is_true = false;
    for (Conjunction& t : terms) {
      std::erase_if(t, [&](const auto& l) { return std::count(common.begin(), common.end(), l) > 0; });
      rest_is_true = rest_is_true || t.empty();
      rest.push_back(std::move(t));
    }
    if (!rest_is_true) conjuncts.push_back(factored(std::move(rest), positive, negative, system));
    return r_conjunction_n(std::move(conjuncts), system);
  }
  if (most_count == 1) {
    std::vector<Expr> disjuncts;
    for (const Conjunction& t : terms) disjuncts.push_back(factored({t}, positive, negative, system));
    return r_disjunction_n(std::move(disjuncts), system);
  }
  std::vector<Conjunction> with, without;
  for (Conjunction& t : terms) (std::count(t.begin(), t.end(), most) ? with : without).push_back(std::move(t));
  return r_or(factored(std::move(with), positive, negative, system),
              factored(std::move(without), positive, negative, system), system);
}

Expr formula_field(const std::vector<SignTerm>& terms, const std::vector<Literal>& literals, const RSystem& system) {
  std::vector<Expr> positive, negative;
  for (const Literal& l : literals) positive.push_back(l.field), negative.push_back(-l.field);
  std::vector<Conjunction> conjunctions;
  for (const SignTerm& t : terms) {
    Conjunction c;
    for (std::size_t l = 0; l < literals.size(); ++l)
      if ((t.mask[l / 64] >> (l % 64)) & 1u) c.emplace_back(l, ((t.bits[l / 64] >> (l % 64)) & 1u) != 0);
    conjunctions.push_back(std::move(c));
  }
  return factored(std::move(conjunctions), positive, negative, system);
}

/// Points of literal `l`'s surface, by Newton steps from `starts`.
std::vector<Vec3> points_on(const Literal& l, const std::vector<Vec3>& starts, double zero) {
  Tape tape(l.field, 3);
  Evaluator<Tuple<3, 1>> eval(tape);
  std::vector<Vec3> out;
  for (Vec3 p : starts) {
    for (int step = 0; step < 8; ++step) {
      const Tuple<3, 1> t = eval.at(p);
      const auto g = t.gradient();
      const double g2 = dot({g[0], g[1], g[2]}, {g[0], g[1], g[2]});
      if (std::abs(t.value()) <= zero) {
        out.push_back(p);
        break;
      }
      if (!(g2 > 1e-12)) break;
      for (std::size_t a = 0; a < 3; ++a) p[a] -= t.value() * g[a] / g2;
    }
  }
  return out;
}

}  // namespace

std::optional<ExactCsg> exact_csg(const CadSolid& solid, const TriangleSurface& tessellation, double deflection,
                                  const RSystem& system, std::string& why_not) {
  try {
    const double scale = solid.millimetres_per_unit;
    Bnd_Box box;
    BRepBndLib::Add(solid.shape, box);
    double lo_mm[3], hi_mm[3];
    box.Get(lo_mm[0], lo_mm[1], lo_mm[2], hi_mm[0], hi_mm[1], hi_mm[2]);
    const double diagonal = std::sqrt(box.SquareExtent()) / scale;
    const double same_length = 1e-7 * diagonal, zero = 1e-10 * diagonal;
    Vec3 lo, hi;
    for (std::size_t a = 0; a < 3; ++a) lo[a] = lo_mm[a] / scale - 0.02 * diagonal, hi[a] = hi_mm[a] / scale + 0.02 * diagonal;

    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(solid.shape, TopAbs_FACE, faces);
    std::vector<Literal> literals;
    std::vector<std::size_t> literal_of_face;
    for (int f = 1; f <= faces.Extent(); ++f) {
      std::optional<Literal> l = literal_of(TopoDS::Face(faces(f)), static_cast<std::size_t>(f), scale, why_not);
      if (!l) return std::nullopt;
      literal_of_face.push_back(add_distinct(literals, std::move(*l), same_length));
    }
    const std::size_t surfaces = literals.size();

    Membership membership(solid.shape, scale, 1e-7 * diagonal * scale, tessellation, 2 * deflection);
    const std::vector<Sample> points =
        samples(lo, hi, 40, tessellation, {1e-3 * diagonal, 1e-2 * diagonal}, 1u, membership);
    std::vector<SignVector> inside, outside;
    std::optional<Vec3> conflict;
    {
      SignsAt signs(literals, zero);
      sign_vectors(points, signs, inside, outside, conflict);
    }
    if (conflict) {
      for (int f = 1; f <= faces.Extent(); ++f)
        if (BRepAdaptor_Surface(TopoDS::Face(faces(f))).GetType() != GeomAbs_Plane)
          add_separators(literals, TopoDS::Face(faces(f)), scale, same_length);
      SignsAt signs(literals, zero);
      sign_vectors(points, signs, inside, outside, conflict);
    }
    if (conflict) {
      why_not = "the faces' surfaces and the curved faces' bounding planes do not separate inside from outside near " +
                at(*conflict);
      return std::nullopt;
    }
    if (inside.empty()) {
      why_not = "no sample point fell inside the solid";
      return std::nullopt;
    }

    // Separators are dropped first: the formula should use as few as it can.
    std::vector<std::size_t> order;
    for (std::size_t l = surfaces; l < literals.size(); ++l) order.push_back(l);
    for (std::size_t l = 0; l < surfaces; ++l) order.push_back(l);
    std::vector<std::vector<std::size_t>> orders(3, order);
    std::reverse(orders[1].begin() + static_cast<std::ptrdiff_t>(literals.size() - surfaces), orders[1].end());
    std::shuffle(orders[2].begin() + static_cast<std::ptrdiff_t>(literals.size() - surfaces), orders[2].end(),
                 std::mt19937(3u));
    const std::vector<SignTerm> terms = prime_terms(inside, outside, literals.size(), orders);
    std::vector<bool> used(literals.size(), false);
    for (const SignTerm& t : terms)
      for (std::size_t l = 0; l < literals.size(); ++l) used[l] = used[l] || ((t.mask[l / 64] >> (l % 64)) & 1u);
    const Expr field = formula_field(terms, literals, system);

    // Checks: signs at fresh points, zeros on the faces, no zero inside.
    const Tape tape(field, 3);
    Evaluator<double> eval(tape);
    std::size_t checked = 0;
    for (const Sample& s : samples(lo, hi, 24, tessellation, {3e-4 * diagonal}, 2u, membership)) {
      const double w = eval.at(s.p);
      if (std::abs(w) <= zero) continue;
      ++checked;
      if ((w > 0) != (s.side > 0)) {
        why_not = "the Boolean formula found from samples puts " + at(s.p) + (w > 0 ? " inside" : " outside") +
                  ", OpenCASCADE's classifier does not";
        return std::nullopt;
      }
    }
    for (const auto& p : tessellation.points)
      if (std::abs(eval.at(p)) > 1e-6 * diagonal) {
        why_not = "the Boolean formula is not zero at " + at(p) + " on the boundary";
        return std::nullopt;
      }
    std::vector<Vec3> starts;
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j)
        for (int k = 0; k < 12; ++k)
          starts.push_back({lo[0] + (hi[0] - lo[0]) * (i + 0.37) / 12, lo[1] + (hi[1] - lo[1]) * (j + 0.61) / 12,
                            lo[2] + (hi[2] - lo[2]) * (k + 0.23) / 12});
    std::size_t surface_points = 0;
    for (std::size_t l = 0; l < literals.size(); ++l) {
      if (!used[l]) continue;
      for (const Vec3& p : points_on(literals[l], starts, zero)) {
        ++surface_points;
        // Zero away from the faces: terms touching there.
        if (std::abs(eval.at(p)) <= 1e-9 * diagonal && membership.off_boundary(p)) {
          why_not = "the Boolean formula vanishes at " + at(p) + ", off the solid's boundary (terms touching there)";
          return std::nullopt;
        }
      }
    }

    std::map<std::string, std::size_t> kinds;
    std::size_t separators = 0;
    for (std::size_t l = 0; l < literals.size(); ++l)
      if (used[l]) literals[l].separator ? ++separators : ++kinds[literals[l].kind];
    std::ostringstream note;
    note << "exact field: the solid as a Boolean formula (R-functions, " << system.name() << ") of " << terms.size()
         << (terms.size() == 1 ? " term" : " terms") << " over the faces' own surfaces (";
    const char* comma = "";
    for (const auto& [kind, n] : kinds) {
      note << comma << n << " " << kind;
      comma = ", ";
    }
    if (separators) note << ", and " << separators << " separating planes";
    note << "); its sign checked at " << checked
         << " points (OpenCASCADE's classifier near the faces), zero at the "
         << tessellation.points.size() << " tessellation nodes, not vanishing inside the solid at "
         << surface_points << " points of its surfaces";
    ExactCsg out{field, {}, {note.str()}};
    for (std::size_t l : literal_of_face) out.face_surfaces.push_back(literals[l].field);
    return out;
  } catch (const Standard_Failure& e) {
    why_not = std::string("OpenCASCADE failed: ") + (e.GetMessageString() ? e.GetMessageString() : "no message");
  } catch (const std::invalid_argument& e) {
    why_not = e.what();
  }
  return std::nullopt;
}

}  // namespace sage::geometry::cad
