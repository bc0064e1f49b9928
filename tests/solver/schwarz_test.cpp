// The multilevel Schwarz preconditioner (schwarz_preconditioner.hpp), the
// default linear solver in 3D: its iterations stay bounded as h shrinks,
// it gives the direct solver's solution, and cut configurations that break
// point smoothers (thin walls a cell or two thick, slivers, cells with a
// single corner inside) do not break it.
#include "manufactured.hpp"

#include <elastic_benchmarks.hpp>
#include <linear_solve.hpp>
#include <solver_fixtures.hpp>

#include <sage/scalars/rfunction.hpp>
#include <sage/solver/elasticity.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace sage::solver {
namespace {

SolverOptions schwarz_options(int degree, double cell_width, double tolerance) {
  SolverOptions options;
  options.degree = degree;
  options.cell_width = cell_width;
  options.linear_solver = LinearSolverKind::Schwarz;
  options.cg_tolerance = tolerance;
  options.estimate_condition = false;
  return options;
}

// Iterations at a fixed tolerance on the plate with a hole (Dirichlet,
// Neumann and Robin faces; the hole and the grid cut each other anyhow),
// from 16 to 32 cells across, two and three levels: measured 42, 42, 42 at
// degree 2. One-level methods double theirs per halving of h.
TEST(Schwarz, IterationsStayBoundedUnderRefinement) {
  const PoissonProblem problem = plate_with_hole();
  std::vector<int> iterations;
  for (const int cells : {16, 24, 32}) {
    const SolveReport report = solve_poisson<3>(problem, schwarz_options(2, 2.0 / cells, 1e-8)).report;
    std::printf("  %d cells: %zu unknowns, %d iterations, %s\n", cells, report.unknowns, report.iterations,
                report.linear_solver.c_str());
    EXPECT_NE(report.linear_solver.find("levels of cell blocks"), std::string::npos) << report.linear_solver;
    EXPECT_LT(report.iterations, 60) << cells << " cells";
    iterations.push_back(report.iterations);
  }
  EXPECT_LE(iterations.back(), 1.3 * iterations.front()) << "from 16 to 32 cells";
}

/// The largest difference of two solutions' B-spline coefficients, over the largest coefficient.
double coefficient_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// The same coefficients as the sparse direct solve, to the tolerance asked
// (a relative residual of 1e-12 times the condition number): Poisson on the
// plate, and elasticity (three components, blocks per component) on the
// thick sphere's octant.
TEST(Schwarz, SolvesWhatTheDirectSolverSolves) {
  const PoissonProblem plate = plate_with_hole();
  SolverOptions options = schwarz_options(2, 2.0 / 20, 1e-12);
  const auto schwarz = solve_poisson<3>(plate, options);
  EXPECT_NE(schwarz.report.linear_solver.find("levels of cell blocks"), std::string::npos)
      << schwarz.report.linear_solver;
  options.linear_solver = LinearSolverKind::Direct;
  const auto direct = solve_poisson<3>(plate, options);
  EXPECT_LT(coefficient_difference(schwarz.spline_coefficients, direct.spline_coefficients), 1e-6);
  EXPECT_NEAR(*schwarz.report.l2_error, *direct.report.l2_error, 1e-6 * *direct.report.l2_error);

  const ElasticityProblem sphere = elastic_benchmarks::thick_sphere(true);
  SolverOptions elastic = schwarz_options(2, sphere.domain.longest_side() / 10, 1e-12);
  const auto elastic_schwarz = solve_elasticity<3>(sphere, elastic);
  EXPECT_NE(elastic_schwarz.report.linear_solver.find("levels of cell blocks"), std::string::npos)
      << elastic_schwarz.report.linear_solver;
  EXPECT_LT(elastic_schwarz.report.iterations, 100);
  elastic.linear_solver = LinearSolverKind::Direct;
  const auto elastic_direct = solve_elasticity<3>(sphere, elastic);
  for (int c = 0; c < 3; ++c)
    EXPECT_LT(
        coefficient_difference(elastic_schwarz.spline_coefficients.col(c), elastic_direct.spline_coefficients.col(c)),
        1e-6)
        << "component " << c;
}

// A wall 0.2 thick, tilted against every axis, cut out of a ball: with
// h = 2/30 and 2/40 it is 3 and 4 cells thick (but only 1.7 and 2.3
// cell diagonals), so almost every cell it meets is cut, many by slivers
// or at a single corner. Dirichlet data of a solution that is not a
// polynomial.
TEST(Schwarz, ThinTiltedWallsWithSliversAndCorners) {
  const RSystem r0 = RSystem::r0();
  const double s = 1.0 / std::sqrt(14.0);
  const std::array<double, 3> normal{s, 2 * s, 3 * s};
  const Expr slab = r_and(
      halfspace({0.1 * normal[0], 0.1 * normal[1], 0.1 * normal[2]}, normal, 3),
      halfspace({-0.1 * normal[0], -0.1 * normal[1], -0.1 * normal[2]}, {-normal[0], -normal[1], -normal[2]}, 3), r0);
  const Expr domain = r_and(slab, ball({0.01, 0.02, 0.03}, 0.93, 3), r0);
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr exact = sin(2.0 * x) * cos(y) + z * z;
  const PoissonProblem problem =
      manufactured::dirichlet_problem(3, domain, exact, exact, {-1.0, -1.0, -1.0}, {1.0, 1.0, 1.0});
  for (const int cells : {30, 40}) {
    SolverOptions options = schwarz_options(2, 2.0 / cells, 1e-12);
    const auto schwarz = solve_poisson<3>(problem, options);
    std::printf("  %d cells: %zu unknowns, %zu cut cells, %d iterations\n", cells, schwarz.report.unknowns,
                schwarz.report.cells_cut, schwarz.report.iterations);
    EXPECT_LT(schwarz.report.iterations, 100) << cells << " cells";
    options.linear_solver = LinearSolverKind::Direct;
    const auto direct = solve_poisson<3>(problem, options);
    EXPECT_LT(coefficient_difference(schwarz.spline_coefficients, direct.spline_coefficients), 1e-6)
        << cells << " cells";
  }
}

/// A B-spline-like system on a box of s^3 unknowns of degree 2: the
/// Kronecker sum K x M x M + M x K x M + M x M x K of banded SPD matrices
/// (couplings up to two places apart, as degree-2 B-splines have), with
/// the diagonal raised at random in one corner, so that the cell blocks
/// there differ (packed inverses) while the others repeat (shared ones).
struct BoxSystem {
  Eigen::SparseMatrix<double> lower;
  SplinePlacement placement;
};

BoxSystem box_system(int s) {
  const double mass[3] = {1.0, 0.25, 0.05}, stiffness[3] = {2.0, -0.9, -0.05};
  auto at = [&](const double* band, int i, int j) { return std::abs(i - j) <= 2 ? band[std::abs(i - j)] : 0.0; };
  std::mt19937 random(3);
  std::uniform_real_distribution<double> raise(0.0, 1.0);
  BoxSystem box;
  box.placement.dimension = 3;
  box.placement.degree = 2;
  std::vector<Eigen::Triplet<double>> entries;
  auto number = [s](int x, int y, int z) { return x + s * (y + s * z); };
  for (int z = 0; z < s; ++z)
    for (int y = 0; y < s; ++y)
      for (int x = 0; x < s; ++x) {
        box.placement.index.push_back({x, y, z});
        box.placement.component.push_back(0);
        for (int c = -2; c <= 2; ++c)
          for (int b = -2; b <= 2; ++b)
            for (int a = -2; a <= 2; ++a) {
              const int X = x + a, Y = y + b, Z = z + c;
              if (X < 0 || Y < 0 || Z < 0 || X >= s || Y >= s || Z >= s || number(X, Y, Z) < number(x, y, z)) continue;
              double v = at(stiffness, x, X) * at(mass, y, Y) * at(mass, z, Z) +
                         at(mass, x, X) * at(stiffness, y, Y) * at(mass, z, Z) +
                         at(mass, x, X) * at(mass, y, Y) * at(stiffness, z, Z);
              if (a == 0 && b == 0 && c == 0 && x < s / 3 && y < s / 3 && z < s / 3) v *= 1.0 + raise(random);
              if (v != 0.0) entries.emplace_back(number(X, Y, Z), number(x, y, z), v);
            }
      }
  box.lower.resize(s * s * s, s * s * s);
  box.lower.setFromTriplets(entries.begin(), entries.end());
  return box;
}

// M^-1 = sum over levels of P (W sum_b R_b^T G_b^T G_b R_b W) P^T is
// symmetric positive definite whether a block's factor is shared (applied
// as matrix products) or packed (distinct blocks): equal both ways round
// to single precision, and CG with it converges fast.
TEST(Schwarz, PreconditionerIsSymmetricPositiveDefinite) {
  const BoxSystem box = box_system(24);
  const SchwarzPreconditioner schwarz(box.lower, box.placement);
  EXPECT_GE(schwarz.levels(), 2u) << schwarz.description();
  const Eigen::Index n = box.lower.rows();
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd a = Eigen::VectorXd::Random(n), b = Eigen::VectorXd::Random(n);
    const Eigen::VectorXd ma = schwarz.solve(a), mb = schwarz.solve(b);
    EXPECT_LT(std::abs(b.dot(ma) - a.dot(mb)), 1e-5 * ma.norm() * b.norm()) << "trial " << trial;
    EXPECT_GT(a.dot(ma), 0.0);
  }
  SolveReport report;
  SplinePlacement placement = box.placement;
  const Eigen::VectorXd right = Eigen::VectorXd::Random(n);
  const Eigen::VectorXd x = solve_symmetric(box.lower, right, LinearSolverKind::Schwarz, 1e-10, report, &placement);
  EXPECT_LT((box.lower.selfadjointView<Eigen::Lower>() * x - right).norm(), 1e-9 * right.norm());
  EXPECT_LT(report.iterations, 40) << report.linear_solver;
}

// The coarse matrices: P^T A P from A's lower triangle, pieces of P's
// columns at a time, equals the dense product's lower triangle, with a P
// of more columns than one piece and rows of P that are empty.
TEST(Schwarz, GalerkinProductEqualsTheDenseOne) {
  const BoxSystem box = box_system(9);
  const Eigen::Index n = box.lower.rows(), coarse = 300;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> weight(0.1, 1.0);
  std::uniform_int_distribution<int> column(0, static_cast<int>(coarse) - 1);
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index u = 0; u < n; ++u)
    if (u % 7 != 3)
      for (int k = 0; k < 4; ++k) entries.emplace_back(u, column(random), weight(random));
  Eigen::SparseMatrix<double> p(n, coarse);
  p.setFromTriplets(entries.begin(), entries.end());
  const Eigen::MatrixXd lower = Eigen::MatrixXd(box.lower);
  const Eigen::MatrixXd a = lower + lower.transpose() - Eigen::MatrixXd(lower.diagonal().asDiagonal());
  const Eigen::MatrixXd dense_p = Eigen::MatrixXd(p);
  const Eigen::MatrixXd expected = (dense_p.transpose() * a * dense_p).triangularView<Eigen::Lower>();
  const Eigen::SparseMatrix<double> product = galerkin_lower(box.lower, p);
  EXPECT_LT((Eigen::MatrixXd(product) - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
  for (Eigen::Index c = 0; c < product.outerSize(); ++c) {  // lower triangle, rows increasing
    Eigen::Index previous = c - 1;
    for (Eigen::SparseMatrix<double>::InnerIterator e(product, c); e; ++e) {
      EXPECT_GT(e.row(), previous);
      previous = e.row();
    }
  }
}

TEST(Schwarz, RefusesAPlacementOfAnotherSize) {
  Eigen::SparseMatrix<double> a(3, 3);
  a.setIdentity();
  SplinePlacement placement;
  placement.index.resize(2);
  placement.component.resize(2, 0);
  EXPECT_THROW(SchwarzPreconditioner(a, placement), std::invalid_argument);
  SolveReport report;
  EXPECT_THROW(solve_symmetric(a, Eigen::VectorXd::Ones(3), LinearSolverKind::Schwarz, 1e-8, report),
               std::invalid_argument);
}

}  // namespace
}  // namespace sage::solver
