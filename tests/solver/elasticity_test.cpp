// Linear elasticity (issue 27) against exact solutions: a linear patch test
// on a curved domain, rigid motions, Lame's cylinder (a free body under
// pressure), Kirsch's plate (rollers, traction, the stress concentration),
// Timoshenko's cantilever and, in 3D, the thick sphere; and the problems
// the solver must refuse.
#include <elastic_benchmarks.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

namespace sage::solver {
namespace {

using namespace elastic_benchmarks;

struct Run {
  double h;
  std::size_t unknowns;
  double l2, energy;
};

template <int D>
std::vector<Run> refine(const char* title, const ElasticityProblem& problem, int degree,
                        const std::vector<int>& cells) {
  std::vector<Run> runs;
  const double longest = problem.domain.longest_side();
  std::printf("  %s, degree %d\n", title, degree);
  for (const int n : cells) {
    SolverOptions options;
    options.degree = degree;
    options.cell_width = longest / n;
    const auto solution = solve_elasticity<D>(problem, options);
    runs.push_back(
        {options.cell_width, solution.report.unknowns, *solution.report.l2_error, *solution.report.energy_error});
    std::printf("    h = %-8.4g unknowns %-7zu L2 %.3e  energy %.3e\n", runs.back().h, runs.back().unknowns,
                runs.back().l2, runs.back().energy);
  }
  return runs;
}

double rate(const std::vector<Run>& runs, double Run::*error) {
  const Run& a = runs[runs.size() - 2];
  const Run& b = runs.back();
  return std::log(a.*error / b.*error) / std::log(a.h / b.h);
}

void expect_optimal(const std::vector<Run>& runs, int degree) {
  EXPECT_GE(rate(runs, &Run::l2), degree + 1 - 0.3);
  EXPECT_GE(rate(runs, &Run::energy), degree - 0.3);
}

/// The disk r < 1 cut at x = -0.5: the cut fixed, the arc loaded.
ElasticityProblem cut_disk(const std::array<Expr, 3>& fixed_values, const std::array<Expr, 3>& arc_traction) {
  ElasticityProblem problem;
  problem.domain.dimension = 2;
  const Expr cut = halfspace({-0.5, 0, 0}, {-1, 0, 0}, 2);
  problem.domain.field = r_and(ball({0, 0, 0}, 1.0, 2), cut, RSystem::r0());
  problem.domain.min = {-1, -1, 0};
  problem.domain.max = {1, 1, 0};
  problem.material = {200.0, 0.25, PlaneMode::Strain};
  problem.parts.push_back(fixed_part("cut", cut, {fixed_values[0], fixed_values[1], std::nullopt}));
  problem.rest = loaded_part("arc", Expr(0.0), arc_traction);
  return problem;
}

/// A quadrilateral with no edge on the grid's lattice: edge 0 fixed to
/// `fixed_values`, edges 1..3 loaded with sigma n (`stress` constant, in
/// VTK's layout), so a linear displacement solves the problem exactly (a
/// curved loaded edge would not: its surface rule is not exact).
ElasticityProblem quadrilateral(const std::array<Expr, 3>& fixed_values, const std::array<double, 6>& stress) {
  const std::array<std::array<double, 2>, 4> corner{{{-0.9, -0.7}, {0.8, -0.9}, {1.0, 0.6}, {-0.6, 0.95}}};
  ElasticityProblem problem;
  problem.domain.dimension = 2;
  problem.domain.min = {-1, -1, 0};
  problem.domain.max = {1, 1, 0};
  problem.material = {200.0, 0.25, PlaneMode::Strain};
  problem.domain.field = Expr(1.0);
  for (int e = 0; e < 4; ++e) {
    const auto& p = corner[e];
    const auto& q = corner[(e + 1) % 4];
    const double length = std::hypot(q[0] - p[0], q[1] - p[1]);
    const double nx = (q[1] - p[1]) / length, ny = -(q[0] - p[0]) / length;  // outward: corners run anticlockwise
    const Expr edge = halfspace({p[0], p[1], 0}, {nx, ny, 0}, 2);
    problem.domain.field = e == 0 ? edge : r_and(problem.domain.field, edge, RSystem::r0());
    const std::string name = "edge" + std::to_string(e);
    if (e == 0) {
      problem.parts.push_back(fixed_part(name, edge, {fixed_values[0], fixed_values[1], std::nullopt}));
    } else {
      problem.parts.push_back(loaded_part(
          name, edge, {Expr(stress[0] * nx + stress[3] * ny), Expr(stress[3] * nx + stress[1] * ny), Expr(0.0)}));
    }
  }
  return problem;
}

TEST(Elasticity, LinearDisplacementIsReproduced) {
  // u = (0.01 + 0.002 x - 0.003 y, -0.02 + 0.004 x + 0.001 y): constant stress.
  const Expr x = Expr::x(), y = Expr::y();
  const Expr ux = 0.01 + 0.002 * x - 0.003 * y, uy = -0.02 + 0.004 * x + 0.001 * y;
  ElasticMaterial material{200.0, 0.25, PlaneMode::Strain};
  const double g[4] = {0.002, -0.003, 0.004, 0.001};
  const auto s = material.stress<2>(g);
  ElasticityProblem problem = quadrilateral({ux, uy, Expr(0.0)}, s);
  problem.exact = std::array<Expr, 3>{ux, uy, Expr(0.0)};
  for (const int degree : {2, 3}) {
    SolverOptions options;
    options.degree = degree;
    options.cell_width = 0.15;
    options.linear_solver = LinearSolverKind::Direct;
    const auto solution = solve_elasticity<2>(problem, options);
    EXPECT_EQ(solution.report.dirichlet_route, "weak (Nitsche)");
    EXPECT_LT(*solution.report.l2_error, 1e-12) << "degree " << degree;
    EXPECT_LT(*solution.report.energy_error, 1e-10) << "degree " << degree;
    typename ElasticitySolution<2>::Probe probe(solution);
    const double at[2] = {0.3, -0.4};
    const auto stress = probe.stress(at);
    for (int v = 0; v < 4; ++v) EXPECT_NEAR(stress[v], s[v], 1e-10 * std::abs(s[0]));
  }
}

TEST(Elasticity, StructureRouteReproducesLinearDisplacementAndConverges) {
  // u_c = w_c Phi_c + g~_c with w_c vanishing on the parts that fix c: on
  // the quadrilateral g~ is the linear data itself; on Kirsch's plate the
  // rollers fix one component each.
  const Expr x = Expr::x(), y = Expr::y();
  const Expr ux = 0.01 + 0.002 * x - 0.003 * y, uy = -0.02 + 0.004 * x + 0.001 * y;
  const double g[4] = {0.002, -0.003, 0.004, 0.001};
  ElasticityProblem patch = quadrilateral({ux, uy, Expr(0.0)}, ElasticMaterial{200.0, 0.25}.stress<2>(g));
  patch.exact = std::array<Expr, 3>{ux, uy, Expr(0.0)};
  SolverOptions options;
  options.degree = 2;
  options.cell_width = 0.15;
  options.dirichlet = DirichletRoute::Structure;
  options.linear_solver = LinearSolverKind::Direct;
  const auto solution = solve_elasticity<2>(patch, options);
  EXPECT_EQ(solution.report.dirichlet_route, "structure");
  EXPECT_LT(*solution.report.l2_error, 1e-11);
  std::vector<double> errors;
  for (const int cells : {16, 32}) {
    options.degree = 3;
    options.cell_width = 4.0 / cells;
    errors.push_back(*solve_elasticity<2>(kirsch_plate(), options).report.energy_error);
  }
  std::printf("  Kirsch plate by the structure, degree 3: energy errors %.3e, %.3e\n", errors[0], errors[1]);
  // Each roller fixes one component on one straight edge, so each w_c is a
  // single halfspace field, smooth, and the energy rate is degree 3's
  // optimal 3 (measured 2.83: 2.745e-3 -> 3.850e-4). Asserted 3 - 0.5, a
  // factor 5.66 per halving: one order lost (rate 2, a factor 4) fails.
  EXPECT_LT(errors[1], errors[0] / std::pow(2.0, 3 - 0.5));
  EXPECT_LT(errors[1], 2e-3);
}

TEST(Elasticity, RigidMotionsLeaveNoStress) {
  // Displacement data of a rigid motion on the cut, no load: u is that
  // motion everywhere, and the stress vanishes.
  const Expr x = Expr::x(), y = Expr::y();
  const Expr ux = 0.1 - 0.05 * y, uy = -0.2 + 0.05 * x;
  ElasticityProblem problem = cut_disk({ux, uy, Expr(0.0)}, {Expr(0.0), Expr(0.0), Expr(0.0)});
  problem.exact = std::array<Expr, 3>{ux, uy, Expr(0.0)};
  SolverOptions options;
  options.degree = 2;
  options.cell_width = 0.15;
  options.linear_solver = LinearSolverKind::Direct;
  const auto solution = solve_elasticity<2>(problem, options);
  EXPECT_EQ(solution.report.elasticity->free_rigid_motions, 0);
  EXPECT_LT(*solution.report.l2_error, 1e-12);
  EXPECT_LT(solution.report.elasticity->max_von_mises, 1e-10 * problem.material.young);
  EXPECT_LT(solution.report.elasticity->strain_energy, 1e-20);
}

TEST(Elasticity, LameCylinderAtOptimalRates) {
  // A free body: three rigid motions fixed by orthogonality, loads balanced.
  const ElasticityProblem problem = lame_cylinder();
  expect_optimal(refine<2>("Lame cylinder", problem, 2, {16, 32}), 2);
  expect_optimal(refine<2>("Lame cylinder", problem, 3, {16, 32}), 3);
  SolverOptions options;
  options.cell_width = 4.0 / 32;
  const auto solution = solve_elasticity<2>(problem, options);
  EXPECT_EQ(solution.report.elasticity->free_rigid_motions, 3);
  EXPECT_LT(*solution.report.elasticity->load_balance, 1e-9);
}

TEST(Elasticity, KirschPlateConcentratesStressThreefold) {
  const ElasticityProblem problem = kirsch_plate();
  expect_optimal(refine<2>("Kirsch plate", problem, 2, {16, 32}), 2);
  expect_optimal(refine<2>("Kirsch plate", problem, 3, {16, 32}), 3);
  SolverOptions options;
  options.cell_width = 4.0 / 32;
  const auto solution = solve_elasticity<2>(problem, options);
  EXPECT_EQ(solution.report.elasticity->free_rigid_motions, 0);
  typename ElasticitySolution<2>::Probe probe(solution);
  const double top_of_hole[2] = {0.0, 1.0};
  const double concentration = probe.stress(top_of_hole)[0];
  std::printf("  sigma_xx at (0, a): %.6f (exact 3)\n", concentration);
  EXPECT_NEAR(concentration, 3.0, 0.005 * 3.0);
  EXPECT_LT(*solution.report.energy_error, 1e-3);
}

TEST(Elasticity, TimoshenkoCantileverAtOptimalRates) {
  const ElasticityProblem problem = timoshenko_cantilever();
  expect_optimal(refine<2>("Timoshenko cantilever", problem, 2, {16, 32}), 2);
  expect_optimal(refine<2>("Timoshenko cantilever", problem, 3, {16, 32}), 3);
}

TEST(Elasticity, ThickSphereConverges) {
  // The octant with symmetry rollers at optimal rates; the whole sphere, a
  // free body whose six rigid motions are fixed by orthogonality, as
  // accurate as the octant on the same cells.
  const auto octant = refine<3>("thick sphere, octant", thick_sphere(true), 2, {6, 12});
  expect_optimal(octant, 2);
  SolverOptions options;
  options.degree = 2;
  options.cell_width = 4.0 / 12;  // the octant's first h
  const auto whole = solve_elasticity<3>(thick_sphere(false), options);
  EXPECT_EQ(whole.report.elasticity->free_rigid_motions, 6);
  std::printf("  whole sphere, h = %.4g: L2 %.3e, energy %.3e\n", options.cell_width, *whole.report.l2_error,
              *whole.report.energy_error);
  EXPECT_LT(*whole.report.l2_error, 1.2 * octant.front().l2);
  EXPECT_LT(*whole.report.energy_error, 1.2 * octant.front().energy);
}

/// The message of the std::invalid_argument that `solve` throws.
std::string refusal(const std::function<void()>& solve) {
  try {
    solve();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(Elasticity, RefusesWhatCannotBePosed) {
  SolverOptions options;
  options.degree = 2;
  options.cell_width = 0.25;
  auto solve = [&](const ElasticityProblem& p) { return [p, options] { solve_elasticity<2>(p, options); }; };

  ElasticityProblem incompressible = lame_cylinder();
  incompressible.material.poisson = 0.5;
  EXPECT_NE(refusal(solve(incompressible)).find("Poisson's ratio"), std::string::npos);
  ElasticityProblem soft = lame_cylinder();
  soft.material.young = 0.0;
  EXPECT_NE(refusal(solve(soft)).find("Young's modulus"), std::string::npos);

  ElasticityProblem both = kirsch_plate();
  both.parts[0].loaded = true;
  EXPECT_NE(refusal(solve(both)).find("part 'left' is both fixed"), std::string::npos);

  // A pull on the outer surface of the free cylinder: a net force.
  ElasticityProblem pulled = lame_cylinder();
  pulled.rest = loaded_part("outer", Expr(0.0), {Expr(1.0), Expr(0.0), Expr(0.0)});
  const std::string message = refusal(solve(pulled));
  EXPECT_NE(message.find("unbalanced loads"), std::string::npos) << message;
}

}  // namespace
}  // namespace sage::solver
