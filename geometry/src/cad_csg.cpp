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
//     classified against the exact solid and by its literals' signs
//     (cad_samples.hpp);
//  3. a sign vector seen both inside and outside (a fillet's cylinder, say,
//     that is material by the fillet and air far from it) needs separating
//     halfspaces: the planes of the curved faces' bounding boxes are added;
//  4. the inside vectors are covered by prime implicants (sign_cover.hpp);
//  5. the union is factored (R-functions stay normalized on faces that two
//     terms share) and checked before use: its sign at fresh points against
//     the classifier, zero at the tessellation's nodes (which lie on the
//     exact faces), and no zero off the boundary at points of its surfaces
//     (where touching terms would vanish).
// Anything unsupported or failing returns why; load_cad then keeps the
// tessellated field.
#include "cad_internal.hpp"
#include "cad_samples.hpp"

#include <sage/expression/primitives.hpp>
#include <sage/tape/evaluator.hpp>

#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <Bnd_Box.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <sstream>

namespace sage::geometry::cad {

namespace {

std::string at(const Vec3& p) {
  std::ostringstream s;
  s << "(" << p[0] << ", " << p[1] << ", " << p[2] << ")";
  return s.str();
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
      if (has_literal(t.mask, l)) c.emplace_back(l, has_literal(t.bits, l));
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

/// What the checks of a formula found.
struct Checks {
  std::string fault;  // empty when all passed
  std::size_t signs = 0, surface_points = 0;
};

/// The formula's checks: its sign at fresh points against the exact
/// solid, zero at the tessellation's nodes (which lie on the exact faces),
/// and no zero off the boundary at points of the literals it uses (where
/// touching terms would vanish).
Checks check_formula(const Expr& field, const std::vector<Literal>& literals, const std::vector<bool>& used,
                     const TriangleSurface& tessellation, const TriangleSurface& curved, const Vec3& lo, const Vec3& hi,
                     double margin, double diagonal, Membership& membership) {
  const double zero = 1e-10 * diagonal;
  const Tape tape(field, 3);
  Evaluator<double> eval(tape);
  Checks out;
  std::vector<Sample> fresh = samples(lo, hi, 24, tessellation, {1.25 * margin}, 20000, 2u, membership);
  for (const Sample& s : samples(lo, hi, 0, curved, {0.25 * margin}, 300, 4u, membership)) fresh.push_back(s);
  for (const Sample& s : fresh) {
    const double w = eval.at(s.p);
    if (std::abs(w) <= zero) continue;
    ++out.signs;
    if ((w > 0) != (s.side > 0)) {
      out.fault = "the Boolean formula found from samples puts " + at(s.p) + (w > 0 ? " inside" : " outside") +
                  ", OpenCASCADE's classifier does not";
      return out;
    }
  }
  for (const auto& p : tessellation.points)
    if (std::abs(eval.at(p)) > 1e-6 * diagonal) {
      out.fault = "the Boolean formula is not zero at " + at(p) + " on the boundary";
      return out;
    }
  std::vector<Vec3> starts;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j)
      for (int k = 0; k < 12; ++k)
        starts.push_back({lo[0] + (hi[0] - lo[0]) * (i + 0.37) / 12, lo[1] + (hi[1] - lo[1]) * (j + 0.61) / 12,
                          lo[2] + (hi[2] - lo[2]) * (k + 0.23) / 12});
  for (std::size_t l = 0; l < literals.size(); ++l) {
    if (!used[l]) continue;
    for (const Vec3& p : points_on(literals[l], starts, zero)) {
      ++out.surface_points;
      if (std::abs(eval.at(p)) <= 1e-9 * diagonal && membership.off_boundary(p)) {
        out.fault = "the Boolean formula vanishes at " + at(p) + ", off the solid's boundary (terms touching there)";
        return out;
      }
    }
  }
  return out;
}

}  // namespace

std::optional<ExactCsg> exact_csg(const CadSolid& solid, const TriangleSurface& tessellation,
                                  const std::vector<std::size_t>& triangle_faces, double deflection,
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
    for (std::size_t a = 0; a < 3; ++a)
      lo[a] = lo_mm[a] / scale - 0.02 * diagonal, hi[a] = hi_mm[a] / scale + 0.02 * diagonal;

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

    std::vector<bool> face_is_curved(static_cast<std::size_t>(faces.Extent()) + 1);
    for (int f = 1; f <= faces.Extent(); ++f)
      face_is_curved[static_cast<std::size_t>(f)] =
          literals[literal_of_face[static_cast<std::size_t>(f - 1)]].kind != "plane";
    TriangleSurface curved{tessellation.points, {}};
    for (std::size_t t = 0; t < tessellation.triangles.size(); ++t)
      if (face_is_curved[triangle_faces[t]]) curved.triangles.push_back(tessellation.triangles[t]);
    // Points near the faces meet the thin cells of the arrangement (at
    // tangent fillets, say). Within `margin` of a curved face only OCCT's
    // slow classifier can tell; few points go there.
    const double margin = 2 * deflection;
    Membership membership(solid.shape, scale, 1e-7 * diagonal * scale, tessellation, curved, margin);
    std::vector<Sample> points =
        samples(lo, hi, 40, tessellation, {1.5 * margin, 1e-2 * diagonal}, 20000, 1u, membership);
    for (const Sample& s : samples(lo, hi, 0, curved, {0.5 * margin}, 300, 3u, membership)) points.push_back(s);
    std::vector<SignVector> inside, outside;
    std::optional<Vec3> conflict;
    {
      SignsAt signs(literals, zero);
      sign_vectors(points, signs, inside, outside, conflict);
    }
    // Separators, as far as needed: the curved faces' bounding planes, then
    // fillets' own.
    for (int round = 0; conflict && round < 2; ++round) {
      for (int f = 1; f <= faces.Extent(); ++f) {
        if (!face_is_curved[static_cast<std::size_t>(f)]) continue;
        const TopoDS_Face& face = TopoDS::Face(faces(f));
        if (round == 0)
          add_bounding_planes(literals, face, scale, same_length);
        else
          add_fillet_separators(literals, face, scale, same_length);
      }
      SignsAt signs(literals, zero);
      sign_vectors(points, signs, inside, outside, conflict);
    }
    if (conflict) {
      why_not = "the faces' surfaces and their separators do not separate inside from outside near " + at(*conflict);
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
      for (std::size_t l = 0; l < literals.size(); ++l) used[l] = used[l] || has_literal(t.mask, l);
    const Expr field = formula_field(terms, literals, system);

    const Checks checks =
        check_formula(field, literals, used, tessellation, curved, lo, hi, margin, diagonal, membership);
    if (!checks.fault.empty()) {
      why_not = checks.fault;
      return std::nullopt;
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
    if (separators) note << ", and " << separators << " separating surfaces";
    note << "); its sign checked at " << checks.signs
         << " points (OpenCASCADE's classifier near the faces), zero at the " << tessellation.points.size()
         << " tessellation nodes, and nonzero off the boundary at " << checks.surface_points
         << " points of its surfaces";
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
