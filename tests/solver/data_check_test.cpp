// Problem data are checked where the solver reads them, before assembly
// (data_check.hpp): a formula that is not finite, a conductivity that is
// not positive or a negative Robin coefficient ends in a DataError naming
// the datum's JSON pointer, its value and the point; data that are bad only
// where the solver does not read them pass.

#include <sage/expression/primitives.hpp>
#include <sage/solver/data_error.hpp>
#include <sage/solver/elasticity.hpp>
#include <sage/solver/poisson.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

namespace sage::solver {
namespace {

const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();

/// The unit disk with u = 0 on its circle, k = 1, f = 1.
PoissonProblem disk() {
  PoissonProblem p;
  p.domain.dimension = 2;
  p.domain.field = ball({0, 0, 0}, 1.0, 2);
  p.domain.min = {-1.1, -1.1, 0};
  p.domain.max = {1.1, 1.1, 0};
  p.source = 1.0;
  return p;
}

/// The square [-1, 1]^2 with a Robin bottom edge (y = -1) and a Neumann top edge, Dirichlet elsewhere.
PoissonProblem square_with_parts() {
  PoissonProblem p;
  p.domain.dimension = 2;
  p.domain.field = box({-1, -1, 0}, {1, 1, 0}, 2, RSystem::r0());
  p.domain.min = {-1.2, -1.2, 0};
  p.domain.max = {1.2, 1.2, 0};
  p.source = 1.0;
  BoundaryPart bottom;
  bottom.name = "bottom";
  bottom.selector = y + 1.0;
  bottom.kind = BoundaryKind::Robin;
  bottom.beta = 2.0;
  BoundaryPart top;
  top.name = "top";
  top.selector = 1.0 - y;
  top.kind = BoundaryKind::Neumann;
  p.parts = {bottom, top};
  return p;
}

SolverOptions coarse(double h) {
  SolverOptions o;
  o.degree = 2;
  o.cell_width = h;
  return o;
}

/// The DataError of solving `p`, or a failure.
DataError poisson_error(const PoissonProblem& p, const SolverOptions& options = coarse(0.25)) {
  try {
    solve_poisson<2>(p, options);
  } catch (const DataError& e) {
    return e;
  }
  ADD_FAILURE() << "no DataError";
  return DataError("none", 0.0, std::nullopt, 2, "");
}

TEST(DataCheck, ConductivityThatIsNotPositiveIsNamedWithItsPoint) {
  PoissonProblem p = disk();
  p.conductivity = 0.0;
  DataError zero = poisson_error(p);
  EXPECT_EQ(zero.datum(), "/conductivity");
  EXPECT_EQ(zero.value(), 0.0);
  EXPECT_FALSE(zero.point()) << "a constant is wrong everywhere";
  EXPECT_NE(std::string(zero.what()).find("/conductivity is 0 everywhere"), std::string::npos) << zero.what();

  p.conductivity = x;  // changes sign inside the disk
  const DataError sign = poisson_error(p);
  EXPECT_EQ(sign.datum(), "/conductivity");
  ASSERT_TRUE(sign.point());
  const auto& at = *sign.point();
  EXPECT_LE(sign.value(), 0.0);
  EXPECT_DOUBLE_EQ(sign.value(), at[0]) << "the value is k's at the point named";
  EXPECT_LE(at[0] * at[0] + at[1] * at[1], 1.0 + 1e-12) << "a point of the domain";
  EXPECT_NE(std::string(sign.what()).find("positive"), std::string::npos) << sign.what();
}

TEST(DataCheck, SourceAndExactSolutionMustBeFinite) {
  PoissonProblem p = disk();
  p.source = log(x * x + y * y - 4.0);  // NaN everywhere in the disk
  const DataError source = poisson_error(p);
  EXPECT_EQ(source.datum(), "/source");
  EXPECT_TRUE(std::isnan(source.value()));
  EXPECT_NE(std::string(source.what()).find("NaN at ("), std::string::npos) << source.what();

  p = disk();
  p.exact = 1.0 / (x - x);  // 1/0: infinite
  EXPECT_EQ(poisson_error(p).datum(), "/exact");
}

TEST(DataCheck, BoundaryDataAreCheckedOnTheirOwnPartOnly) {
  // log(y + 1.5) is NaN below y = -1.5, outside the square: fine as any part's data.
  // sqrt(y) is NaN on the bottom edge (y = -1) but finite on the top one.
  PoissonProblem p = square_with_parts();
  p.parts[1].flux = sqrt(y);  // the top's flux: read at y = 1 only
  p.rest.value = log(y + 1.5);
  EXPECT_NO_THROW(solve_poisson<2>(p, coarse(0.25)));

  p.parts[0].flux = sqrt(y);  // the bottom's flux: NaN at y = -1
  const DataError flux = poisson_error(p);
  EXPECT_EQ(flux.datum(), "/boundary/bottom/flux");
  ASSERT_TRUE(flux.point());
  EXPECT_NEAR((*flux.point())[1], -1.0, 1e-9) << "a point of the bottom edge";
}

TEST(DataCheck, NegativeRobinCoefficientIsRefused) {
  PoissonProblem p = square_with_parts();
  p.parts[0].beta = -5.0;
  const DataError constant = poisson_error(p);
  EXPECT_EQ(constant.datum(), "/boundary/bottom/beta");
  EXPECT_EQ(constant.value(), -5.0);
  EXPECT_NE(std::string(constant.what()).find("coercive"), std::string::npos) << constant.what();

  p.parts[0].beta = x;  // negative on the left half of the bottom edge
  const DataError varying = poisson_error(p);
  EXPECT_EQ(varying.datum(), "/boundary/bottom/beta");
  ASSERT_TRUE(varying.point());
  EXPECT_LT((*varying.point())[0], 0.0);
  EXPECT_NEAR((*varying.point())[1], -1.0, 1e-9);
}

TEST(DataCheck, DataOfScalesDoublePrecisionCannotCarryAreNamed) {
  // Finite data whose products overflow, a conductivity whose stiffness
  // underflows, and a Robin coefficient so large against k / h that the
  // system is singular to rounding (CG then met p.Ap < 0 at iteration 1,035).
  PoissonProblem p = square_with_parts();
  p.source = 1e200 * (1.0 + x * x);
  DataError huge = poisson_error(p);
  EXPECT_EQ(huge.datum(), "/source");
  EXPECT_NE(std::string(huge.what()).find("overflow"), std::string::npos) << huge.what();
  p = square_with_parts();
  p.conductivity = 1e-200;
  EXPECT_EQ(poisson_error(p).datum(), "/conductivity");
  p = square_with_parts();
  p.parts[0].beta = 1e30;
  const DataError biot = poisson_error(p);
  EXPECT_EQ(biot.datum(), "/boundary/bottom/beta");
  EXPECT_NE(std::string(biot.what()).find("beta h / k"), std::string::npos) << biot.what();
  p.conductivity = 1e25;  // the same beta against a conductivity that large is a Robin condition
  EXPECT_NO_THROW(solve_poisson<2>(p, coarse(0.25)));
}

TEST(DataCheck, StructureRouteReadsDirichletValuesThroughoutTheDomain) {
  // sqrt(0.5 - y) is finite on the bottom edge, but the structure's
  // extension g~ evaluates every Dirichlet value inside the domain too,
  // where it is NaN above y = 0.5. The weak route reads it on the edge only.
  PoissonProblem p = square_with_parts();
  p.parts[0].name = "bottom/edge";  // a name that JSON pointers escape
  p.parts[0].kind = BoundaryKind::Dirichlet;
  p.parts[0].value = sqrt(0.5 - y);
  p.rest.kind = BoundaryKind::Neumann;  // the structure route's default must not be Dirichlet
  EXPECT_NO_THROW(solve_poisson<2>(p, coarse(0.25)));
  SolverOptions structure = coarse(0.25);
  structure.dirichlet = DirichletRoute::Structure;
  const DataError e = poisson_error(p, structure);
  EXPECT_EQ(e.datum(), "/boundary/bottom~1edge/value");
  ASSERT_TRUE(e.point());
  EXPECT_GT((*e.point())[1], 0.5);
}

TEST(DataCheck, ElasticityLoadsAndBodyForceIn3D) {
  ElasticityProblem p;
  p.domain.dimension = 3;
  p.domain.field = box({0, 0, 0}, {2, 1, 1}, 3, RSystem::r0());
  p.domain.min = {-0.1, -0.1, -0.1};
  p.domain.max = {2.1, 1.1, 1.1};
  p.material.young = 100.0;
  p.material.poisson = 0.3;
  ElasticPart fixed;
  fixed.name = "fixed";
  fixed.selector = x;
  fixed.displacement = {Expr(0.0), Expr(0.0), Expr(0.0)};
  ElasticPart load;
  load.name = "load";
  load.selector = 2.0 - x;
  load.traction = {Expr(0.0), Expr(0.0), log(z - 0.5)};  // NaN on the lower half of the end face
  load.loaded = true;
  p.parts = {fixed, load};
  SolverOptions options = coarse(0.25);
  options.degree = 1;
  try {
    solve_elasticity<3>(p, options);
    FAIL() << "no DataError";
  } catch (const DataError& e) {
    EXPECT_EQ(e.datum(), "/boundary/load/traction/2");
    ASSERT_TRUE(e.point());
    EXPECT_NEAR((*e.point())[0], 2.0, 1e-9);
    EXPECT_LT((*e.point())[2], 0.5);
  }
  p.parts[1].traction[2] = 1.0;
  p.body_force[1] = 1.0 / (y - y);
  try {
    solve_elasticity<3>(p, options);
    FAIL() << "no DataError";
  } catch (const DataError& e) {
    EXPECT_EQ(e.datum(), "/body_force/1");
    EXPECT_TRUE(std::isinf(e.value()));
  }
}

}  // namespace
}  // namespace sage::solver
