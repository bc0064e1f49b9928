#include <sage/solver/domain_probe.hpp>
#include <sage/solver/solution_samples.hpp>

#include <sage/sampling/pruned_grid.hpp>
#include <sage/tape/evaluator.hpp>

#include <algorithm>
#include <cmath>

namespace sage::solver {

Grid solution_grid(int dimension, const std::array<double, 3>& min, const std::array<double, 3>& max, double cell_width,
                   const std::optional<std::array<int, 3>>& points) {
  Grid grid;
  grid.dimension = dimension;
  grid.lo = min;
  grid.hi = max;
  if (points) {
    grid.points = *points;
  } else {
    const int per_cell = dimension == 2 ? 4 : 2, cap = dimension == 2 ? 401 : 97;
    for (int a = 0; a < dimension; ++a)
      grid.points[a] =
          std::clamp(static_cast<int>(std::ceil((grid.hi[a] - grid.lo[a]) / cell_width)) * per_cell + 1, 2, cap);
  }
  if (dimension == 2) grid.points[2] = 1;
  return grid;
}

bool omega_from_patches(const std::shared_ptr<const Tape>& domain) {
  return domain && domain->code().size() > kLargeField;
}

template <int D>
std::vector<double> omega_on_grid(const std::shared_ptr<const Tape>& domain,
                                  const std::shared_ptr<const MeshDomain>& mesh, double cell_width, const Grid& grid) {
  std::vector<double> omega(grid.size());
  if (omega_from_patches(domain)) {
    Approximation approximation;
    approximation.tolerance = kOutputOmegaTolerance * grid.diagonal();
    for_each_grid_point_pruned<double>(
        *domain, grid, [&](std::size_t i, const auto& results) { omega[i] = results.result(0); }, {}, &approximation);
    return omega;
  }
#pragma omp parallel
  {
    DomainProbe<D> probe(domain, mesh, cell_width);
#pragma omp for schedule(dynamic, 1024)
    for (std::size_t i = 0; i < grid.size(); ++i) omega[i] = probe.at(grid.point(i).data());
  }
  return omega;
}

template <int D>
std::vector<PointArray> sample_solution(const PoissonSolution<D>& solution, const std::optional<Expr>& exact,
                                        const std::vector<std::array<double, 3>>& points) {
  const std::size_t n = points.size();
  PointArray u{"u", 1, std::vector<double>(n)}, grad{"grad_u", 3, std::vector<double>(3 * n, 0.0)};
  PointArray u_exact{"u_exact", 1, {}}, error{"error", 1, {}};
  std::optional<Tape> exact_tape;
  if (exact) {
    exact_tape.emplace(*exact, D);
    u_exact.values.resize(n);
    error.values.resize(n);
  }
#pragma omp parallel
  {
    typename PoissonSolution<D>::Probe probe(solution);
    std::optional<Evaluator<double>> exact_eval;
    if (exact_tape) exact_eval.emplace(*exact_tape);
#pragma omp for schedule(dynamic, 1024)
    for (std::size_t i = 0; i < n; ++i) {
      const double* p = points[i].data();
      double g[3] = {0, 0, 0};
      u.values[i] = probe.at(p, g);
      for (int a = 0; a < D; ++a) grad.values[3 * i + static_cast<std::size_t>(a)] = g[a];
      if (!exact_eval) continue;
      exact_eval->evaluate(p);
      u_exact.values[i] = exact_eval->result();
      error.values[i] = u.values[i] - u_exact.values[i];
    }
  }
  std::vector<PointArray> arrays{u, grad};
  if (exact) {
    arrays.push_back(u_exact);
    arrays.push_back(error);
  }
  return arrays;
}

template <int D>
std::vector<PointArray> sample_solution(const ElasticitySolution<D>& solution,
                                        const std::optional<std::array<Expr, 3>>& exact,
                                        const std::vector<std::array<double, 3>>& points) {
  const std::size_t n = points.size();
  PointArray displacement{"displacement", 3, std::vector<double>(3 * n, 0.0)},
      stress{"stress", 6, std::vector<double>(6 * n)}, mises{"von_mises", 1, std::vector<double>(n)};
  PointArray displacement_exact{"displacement_exact", 3, {}}, error{"displacement_error", 3, {}};
  std::optional<Tape> exact_tape;
  if (exact) {
    exact_tape.emplace(std::vector<Expr>(exact->begin(), exact->begin() + D), D);
    displacement_exact.values.assign(3 * n, 0.0);
    error.values.assign(3 * n, 0.0);
  }
#pragma omp parallel
  {
    typename ElasticitySolution<D>::Probe probe(solution);
    std::optional<Evaluator<double>> exact_eval;
    if (exact_tape) exact_eval.emplace(*exact_tape);
#pragma omp for schedule(dynamic, 1024)
    for (std::size_t i = 0; i < n; ++i) {
      const double* p = points[i].data();
      double u[D], g[D * D];
      probe.at(p, u, g);
      const auto s = solution.material.template stress<D>(g);
      for (int a = 0; a < D; ++a) displacement.values[3 * i + static_cast<std::size_t>(a)] = u[a];
      for (int v = 0; v < 6; ++v) stress.values[6 * i + static_cast<std::size_t>(v)] = s[static_cast<std::size_t>(v)];
      mises.values[i] = von_mises(s);
      if (!exact_eval) continue;
      exact_eval->evaluate(p);
      for (int a = 0; a < D; ++a) {
        const auto at = 3 * i + static_cast<std::size_t>(a);
        displacement_exact.values[at] = exact_eval->result(static_cast<std::size_t>(a));
        error.values[at] = u[a] - displacement_exact.values[at];
      }
    }
  }
  std::vector<PointArray> arrays{displacement, stress, mises};
  if (exact) {
    arrays.push_back(displacement_exact);
    arrays.push_back(error);
  }
  return arrays;
}

template std::vector<double> omega_on_grid<2>(const std::shared_ptr<const Tape>&,
                                              const std::shared_ptr<const MeshDomain>&, double, const Grid&);
template std::vector<double> omega_on_grid<3>(const std::shared_ptr<const Tape>&,
                                              const std::shared_ptr<const MeshDomain>&, double, const Grid&);
template std::vector<PointArray> sample_solution<2>(const PoissonSolution<2>&, const std::optional<Expr>&,
                                                    const std::vector<std::array<double, 3>>&);
template std::vector<PointArray> sample_solution<3>(const PoissonSolution<3>&, const std::optional<Expr>&,
                                                    const std::vector<std::array<double, 3>>&);
template std::vector<PointArray> sample_solution<2>(const ElasticitySolution<2>&,
                                                    const std::optional<std::array<Expr, 3>>&,
                                                    const std::vector<std::array<double, 3>>&);
template std::vector<PointArray> sample_solution<3>(const ElasticitySolution<3>&,
                                                    const std::optional<std::array<Expr, 3>>&,
                                                    const std::vector<std::array<double, 3>>&);

}  // namespace sage::solver
