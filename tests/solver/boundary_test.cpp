// The Dirichlet structure: transfinite interpolation takes each piece's
// data on its piece; omega_D vanishes exactly on the Dirichlet parts and is
// oriented positive inside; problems the solver does not pose are refused,
// pure Neumann problems flagged.
#include <sage/expression/primitives.hpp>
#include <sage/solver/boundary_structure.hpp>
#include <sage/solver/problem.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace sage::solver {
namespace {

double at(const Expr& e, double x, double y) {
  Tape tape(e, 2);
  Evaluator<double> eval(tape);
  return eval.at({x, y, 0});
}

TEST(Transfinite, TakesEachPiecesDataOnItsPiece) {
  const Expr x = Expr::x(), y = Expr::y();
  // Pieces: the lines x = 1 and y = 1 (fields vanish there), data differ.
  const Expr g = transfinite_interpolation({1.0 - x, 1.0 - y}, {2.0 + y, 3.0 * x});
  for (double t : {-0.7, 0.0, 0.4}) {
    EXPECT_NEAR(at(g, 1.0, t), 2.0 + t, 1e-14);
    EXPECT_NEAR(at(g, t, 1.0), 3.0 * t, 1e-14);
  }
  // Between the pieces: a weighted mean of the two data.
  const double inside = at(g, 0.2, -0.3);
  EXPECT_GT(inside, std::min(2.0 - 0.3, 0.6) - 1e-12);
  EXPECT_LT(inside, std::max(2.0 - 0.3, 0.6) + 1e-12);
}

PoissonProblem square_with_hole() {
  PoissonProblem p;
  p.domain.dimension = 2;
  const Expr outer = box({-1, -1, 0}, {1, 1, 0}, 2, RSystem::r0());
  const Expr hole = ball({0, 0, 0}, 0.4, 2);
  p.domain.field = r_and(outer, -hole, RSystem::r0());
  p.parts = {{"outer", outer, BoundaryKind::Dirichlet, 1.0}, {"hole", hole, BoundaryKind::Dirichlet, 5.0}};
  return p;
}

TEST(BoundaryStructure, SelectorsAreOrientedAndDataInterpolated) {
  PoissonProblem p = square_with_hole();
  const BoundaryStructure s = boundary_structure(boundary_split(p), {0.7, 0.0, 0.0});
  // The hole's disk field is negative in the domain: flipped.
  EXPECT_GT(at(s.selectors[1], 0.7, 0.0), 0.0);
  EXPECT_GT(at(s.selectors[0], 0.7, 0.0), 0.0);
  EXPECT_FALSE(s.has_weak_parts);
  EXPECT_NEAR(at(s.dirichlet_extension, 0.4, 0.0), 5.0, 1e-12);
  EXPECT_NEAR(at(s.dirichlet_extension, 1.0, 0.3), 1.0, 1e-12);
  EXPECT_NEAR(at(s.dirichlet_weight, 1.0, 0.3), 0.0, 1e-12);
}

TEST(BoundaryStructure, MixedConditionsWeightVanishesOnDirichletPartsOnly) {
  PoissonProblem p = square_with_hole();
  p.parts[1].kind = BoundaryKind::Robin;
  p.parts[1].beta = 1.0;
  p.rest = p.parts[1];
  const BoundaryStructure s = boundary_structure(boundary_split(p), {0.7, 0.0, 0.0});
  EXPECT_TRUE(s.has_weak_parts);
  EXPECT_NEAR(at(s.dirichlet_weight, 1.0, 0.3), 0.0, 1e-12);
  EXPECT_GT(at(s.dirichlet_weight, 0.4, 0.0), 0.1);  // free on the Robin hole
  EXPECT_NEAR(at(s.dirichlet_extension, 1.0, 0.3), 1.0, 1e-12);
}

TEST(BoundaryStructure, RefusesWhatItCannotPose) {
  PoissonProblem p = square_with_hole();
  p.parts[1].kind = BoundaryKind::Neumann;  // rest stays Dirichlet
  EXPECT_THROW(boundary_structure(boundary_split(p), {0.7, 0.0, 0.0}), std::invalid_argument);
  // Nitsche's method needs no omega_D: the same problem is posed.
  EXPECT_FALSE(boundary_structure(boundary_split(p), {0.7, 0.0, 0.0}, false).pure_neumann);
  p.rest.kind = BoundaryKind::Neumann;
  p.parts[0].kind = BoundaryKind::Neumann;
  EXPECT_TRUE(
      boundary_structure(boundary_split(p), {0.7, 0.0, 0.0}).pure_neumann);  // posed with zero mean (poisson.hpp)
  p.parts[1].kind = BoundaryKind::Robin;                                     // beta = 0: still Neumann
  EXPECT_TRUE(boundary_structure(boundary_split(p), {0.7, 0.0, 0.0}).pure_neumann);
  p.parts[1].beta = 1.0;
  EXPECT_FALSE(boundary_structure(boundary_split(p), {0.7, 0.0, 0.0}).pure_neumann);
  p = square_with_hole();
  EXPECT_THROW(boundary_structure(boundary_split(p), {0.4, 0.0, 0.0}),
               std::invalid_argument);  // selector zero at the point
}

TEST(BoundaryStructure, TakesASplitOfAnyPhysics) {
  // An elasticity component's split: the outer part fixes it at 1, the
  // hole and the rest are loaded (weak).
  const PoissonProblem p = square_with_hole();
  BoundarySplit split;
  split.dimension = 2;
  split.field = p.domain.field;
  split.parts = {{"outer", p.parts[0].selector, Expr(1.0)}, {"hole", p.parts[1].selector, std::nullopt}};
  split.rest = {"default", Expr(0.0), std::nullopt};
  BoundaryStructure s = boundary_structure(split, {0.7, 0.0, 0.0});
  EXPECT_TRUE(s.has_weak_parts);
  EXPECT_FALSE(s.pure_neumann);
  EXPECT_NEAR(at(s.dirichlet_weight, 1.0, 0.3), 0.0, 1e-12);
  EXPECT_GT(at(s.dirichlet_weight, 0.4, 0.0), 0.1);
  EXPECT_NEAR(at(s.dirichlet_extension, 1.0, 0.3), 1.0, 1e-12);
  split.parts[0].value.reset();  // nothing holds the component
  s = boundary_structure(split, {0.7, 0.0, 0.0});
  EXPECT_TRUE(s.pure_neumann);
  EXPECT_NEAR(at(s.dirichlet_weight, 1.0, 0.3), 1.0, 1e-12);
}

TEST(BoundaryStructure, PoissonSplitsByKind) {
  PoissonProblem p = square_with_hole();
  p.parts[1].kind = BoundaryKind::Robin;  // beta = 0: a Neumann part
  BoundarySplit split = boundary_split(p);
  ASSERT_EQ(split.parts.size(), 2u);
  ASSERT_TRUE(split.parts[0].value);
  EXPECT_EQ(split.parts[0].value->id(), p.parts[0].value.id());
  EXPECT_FALSE(split.parts[1].value);
  EXPECT_FALSE(split.parts[1].robin);
  p.parts[1].beta = 2.0;
  split = boundary_split(p);
  EXPECT_TRUE(split.parts[1].robin);
  EXPECT_TRUE(split.rest.value);  // the rest stays Dirichlet u = 0
}

}  // namespace
}  // namespace sage::solver
