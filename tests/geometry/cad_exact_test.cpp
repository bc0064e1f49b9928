// Exact fields of CAD solids bounded by analytic faces (cad_csg.cpp): the
// Boolean formula over the faces' surfaces against OCCT's classifier, zero
// and of unit gradient on the exact faces; the fallback to the
// tessellation; the solver on them, as accurate as on the same solid
// written as CSG, and converging at the optimal rate on a curved part.
#include <sage/geometry/cad_model.hpp>
#include <sage/geometry/model.hpp>
#include <sage/problems/problem_file.hpp>
#include <sage/solver/poisson.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <gtest/gtest.h>
#include <cad_fixtures.hpp>
#include <test_files.hpp>

#include "../../geometry/src/sign_cover.hpp"

#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>

#include <cmath>
#include <fstream>
#include <functional>
#include <random>
#include <variant>

namespace sage::geometry {
namespace {

std::string path_of(const std::string& name) { return (test::scratch_dir() / name).string(); }

bool has_note(const Model& m, const std::string& text) {
  for (const std::string& n : m.notes)
    if (n.find(text) != std::string::npos) return true;
  return false;
}

/// An L of two plates, the inner edge filleted, a hole through the base:
/// a union whose terms would touch along the plane x = 1 if the formula
/// were split there, and a fillet whose cylinder is material near the
/// corner and air far from it (separating planes needed).
/// The union of a and b with the edges whose midpoint `picks` filleted.
TopoDS_Shape fused_and_filleted(const TopoDS_Shape& a, const TopoDS_Shape& b, double radius,
                                const std::function<bool(const gp_Pnt&)>& picks) {
  BRepAlgoAPI_Fuse fuse(a, b);
  fuse.SimplifyResult();
  const TopoDS_Shape joined = fuse.Shape();
  BRepFilletAPI_MakeFillet fillet(joined);
  for (TopExp_Explorer e(joined, TopAbs_EDGE); e.More(); e.Next()) {
    Standard_Real first, last;
    const Handle(Geom_Curve) curve = BRep_Tool::Curve(TopoDS::Edge(e.Current()), first, last);
    if (picks(curve->Value(0.5 * (first + last)))) fillet.Add(radius, TopoDS::Edge(e.Current()));
  }
  return fillet.Shape();
}

TopoDS_Shape filleted_l() {
  // The inner edge, along y at x = 1, z = 1.
  const TopoDS_Shape rounded = fused_and_filleted(
      BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 4, 2, 1).Shape(), BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 1, 2, 3).Shape(), 0.4,
      [](const gp_Pnt& q) { return std::abs(q.X() - 1) < 1e-9 && std::abs(q.Z() - 1) < 1e-9; });
  const TopoDS_Shape hole = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(2.8, 1, -1), gp_Dir(0, 0, 1)), 0.3, 3).Shape();
  return BRepAlgoAPI_Cut(rounded, hole).Shape();
}

/// A boss on a plate, filleted at its base (a torus, air inside its
/// tube, material between it and the boss: separated by the cylinder and
/// the plane of the tube's centre circle), a hole through it countersunk
/// by a cone.
TopoDS_Shape filleted_boss() {
  // The boss's base circle, radius 8 at z = 5.
  TopoDS_Shape part = fused_and_filleted(
      BRepPrimAPI_MakeBox(gp_Pnt(-20, -20, 0), 40, 40, 5).Shape(),
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 5), gp_Dir(0, 0, 1)), 8, 10).Shape(), 2.0,
      [](const gp_Pnt& q) { return std::abs(q.Z() - 5) < 1e-9 && std::abs(std::hypot(q.X(), q.Y()) - 8) < 1e-6; });
  part =
      BRepAlgoAPI_Cut(part, BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, -1), gp_Dir(0, 0, 1)), 3, 20).Shape()).Shape();
  return BRepAlgoAPI_Cut(part, BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(0, 0, 12), gp_Dir(0, 0, 1)), 3, 6, 3).Shape())
      .Shape();
}

/// A box with every edge rounded: cylinders, and spheres at the corners.
TopoDS_Shape rounded_box() {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 10, 6, 4).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  for (TopExp_Explorer e(box, TopAbs_EDGE); e.More(); e.Next()) fillet.Add(1.0, TopoDS::Edge(e.Current()));
  return fillet.Shape();
}

/// Checks the exact field of `solid` (written as STEP): its signs against
/// OCCT's classifier at `points` random points of `box` (up to 1e-9 of the
/// boundary), and on every face, at each triangle's centroid moved onto
/// the face's exact surface, a zero value with a unit gradient (the
/// formula is normalized there).
void expect_exact(const TopoDS_Shape& solid, const std::string& name, const Bnd_Box& box, int points) {
  const std::string path = path_of(name + ".step");
  test::write_step(solid, path);
  const Model m = load_model(path);
  ASSERT_FALSE(m.field_follows_surface) << name;
  EXPECT_TRUE(has_note(m, "exact field")) << name;

  const Tape tape(m.field, 3);
  Evaluator<double> eval(tape);
  std::mt19937_64 rng(7);
  double lo[3], hi[3];
  box.Get(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  int inside = 0, compared = 0, mismatches = 0;
  for (int k = 0; k < points; ++k) {
    std::array<double, 3> p;
    for (int a = 0; a < 3; ++a) p[a] = std::uniform_real_distribution<double>(lo[a], hi[a])(rng);
    BRepClass3d_SolidClassifier classifier(solid, gp_Pnt(p[0], p[1], p[2]), 1e-9);
    if (classifier.State() == TopAbs_ON) continue;
    ++compared;
    const bool in = classifier.State() == TopAbs_IN;
    inside += in;
    mismatches += (eval.at(p) > 0) != in;
  }
  EXPECT_GT(compared, points * 99 / 100) << name;
  EXPECT_GT(inside, points / 10) << name;
  EXPECT_EQ(mismatches, 0) << name;

  Evaluator<Tuple<3, 1>> tuples(tape);
  double worst_value = 0, worst_gradient = 0;
  for (std::size_t t = 0; t < m.surface->triangles.size(); ++t) {
    const auto& tri = m.surface->triangles[t];
    std::array<double, 3> c{};
    for (int a = 0; a < 3; ++a)
      c[a] = (m.surface->points[tri[0]][a] + m.surface->points[tri[1]][a] + m.surface->points[tri[2]][a]) / 3;
    c = test::onto_surface(*m.faces[m.triangle_faces[t] - 1].exact_surface, c);
    const Tuple<3, 1> w = tuples.at(c);
    const auto g = w.gradient();
    worst_value = std::max(worst_value, std::abs(w.value()));
    worst_gradient = std::max(worst_gradient, std::abs(std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) - 1));
  }
  EXPECT_LT(worst_value, 1e-12) << name;
  EXPECT_LT(worst_gradient, 1e-9) << name;
}

Bnd_Box box_of(double x0, double y0, double z0, double x1, double y1, double z1) {
  Bnd_Box b;
  b.Update(x0, y0, z0, x1, y1, z1);
  return b;
}

TEST(CadExact, FilletedLIsAnExactFormula) {
  expect_exact(filleted_l(), "filleted_l", box_of(-0.5, -0.5, -0.5, 4.5, 2.5, 3.5), 10000);
}

TEST(CadExact, FilletedBossWithTorusAndCone) {
  expect_exact(filleted_boss(), "boss", box_of(-21, -21, -1, 21, 21, 16), 3000);
}

TEST(CadExact, RoundedBoxWithSphericalCorners) {
  expect_exact(rounded_box(), "rounded_box", box_of(-0.5, -0.5, -0.5, 10.5, 6.5, 4.5), 3000);
}

TEST(CadExact, FreeFormFacesKeepTheTessellation) {
  // The block with its faces converted to B-splines: no analytic surface.
  const TopoDS_Shape nurbs = BRepBuilderAPI_NurbsConvert(test::block_with_channel()).Shape();
  const std::string path = path_of("nurbs_block.step");
  test::write_step(nurbs, path);
  const Model m = load_model(path);
  EXPECT_TRUE(m.field_follows_surface);
  EXPECT_TRUE(has_note(m, "no exact field: face 1 is not a plane, cylinder, cone, sphere or torus (bspline)"));
  // So does method brep, asked for.
  LoadOptions brep;
  brep.method = "brep";
  const std::string block = path_of("block_exact.step");
  test::write_step(test::block_with_channel(), block);
  EXPECT_TRUE(load_model(block, brep).field_follows_surface);
  EXPECT_FALSE(load_model(block).field_follows_surface);
}

TEST(CadExact, PrimeTermsOverlapWhereAGreedyCoverWouldSplit) {
  // Literals: 0 is x > 0, 1 is x > 1, 2 is z < 1, 3 is z < 3. The solid is
  // an L: the wall 0 < x < 1, z < 3 and the base x > 0, z < 1. Vectors as
  // samples see them; the base's right part comes first.
  const auto v = [](int a, int b, int c, int d) {
    return SignVector{static_cast<std::uint64_t>(a | b << 1 | c << 2 | d << 3)};
  };
  const std::vector<SignVector> inside{v(1, 1, 1, 1), v(1, 0, 1, 1), v(1, 0, 0, 1)};
  const std::vector<SignVector> outside{v(0, 0, 1, 1), v(0, 0, 0, 1), v(1, 1, 0, 1),
                                        v(1, 0, 0, 0), v(1, 1, 0, 0), v(0, 0, 0, 0)};
  // The first vector expands to x > 1 AND z < 1, which touches the wall
  // along x = 1 (the R-disjunction would vanish there). Expanding every
  // inside vector, not only the uncovered ones, finds x > 0 AND z < 1,
  // and the touching term, inside it, is dropped.
  const auto terms = prime_terms(inside, outside, 4, {{0, 1, 2, 3}});
  ASSERT_EQ(terms.size(), 2u);
  bool spanning_base = false, wall = false;
  for (const SignTerm& t : terms) {
    spanning_base = spanning_base || (t.mask[0] == 0b0101 && t.bits[0] == 0b0101);
    wall = wall || (t.mask[0] == 0b1011 && t.bits[0] == 0b1001);
  }
  EXPECT_TRUE(spanning_base);
  EXPECT_TRUE(wall);
  for (const SignTerm& t : terms) {
    for (const SignVector& o : outside) EXPECT_FALSE(t.covers(o));
  }
  for (const SignVector& i : inside) {
    bool covered = false;
    for (const SignTerm& t : terms) covered = covered || t.covers(i);
    EXPECT_TRUE(covered);
  }
  EXPECT_THROW(prime_terms({v(1, 0, 1, 1)}, {v(1, 0, 1, 1)}, 4, {{0, 1, 2, 3}}), std::invalid_argument);
}

}  // namespace
}  // namespace sage::geometry
