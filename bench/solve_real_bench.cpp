// solve_real_bench: sage solve on real shapes with no exact solution
// (issue 24): closed triangle meshes (the bunny, 75,408 triangles; a joint
// and a pinion from CAD) and a lake with 56 islands (718 edges, GeoJSON),
// u = 0 on the boundary, unit source, degree 2, Dirichlet conditions by
// Nitsche's method (the default).
//
// Per refinement: unknowns, cut cells, quadrature points, CPU seconds per
// stage (process CPU, all threads), wall seconds, peak resident MB of the
// solve (with the model already read), and
// J = the integral of u over the domain (= the energy |grad u|^2, since
// f = 1), with the difference to the previous level and the ratio of
// successive differences: convergence without an exact solution.
//
// `lake` also times the whole `sage solve` command (reading, classifying,
// solving, writing the .vtu) on one thread at 128 cells, the issue's goal.
//
//   solve_real_bench [meshes|lake|all] [CELLS...]   (OMP_NUM_THREADS=1 for one-thread figures)

#include <sage/geometry/model.hpp>
#include <sage/solver/poisson.hpp>

#include "bench_problems.hpp"
#include "bench_support.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

using namespace sage;
using namespace sage::solver;
using sage::bench::peak_megabytes;
using sage::bench::reset_peak;
using sage::bench::zero_dirichlet;

std::string shared(const std::string& name) { return sage::bench::shared_data(name); }

/// J = the integral of u, from the solver's own volume rule.
template <int D>
double integral_of_u(const PoissonSolution<D>& solution) {
  const QuadratureDump& q = solution.quadrature;
  double sum = 0.0;
#pragma omp parallel reduction(+ : sum)
  {
    typename PoissonSolution<D>::Probe probe(solution);
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < q.weights.size(); ++k)
      if (q.on_surface[k] == 0.0) sum += q.weights[k] * probe.at(&q.coordinates[3 * k]);
  }
  return sum;
}

template <int D>
void refinement(const std::string& title, const geometry::Model& model, const std::vector<int>& cells_across) {
  const PoissonProblem problem = zero_dirichlet(model);
  const double longest = problem.domain.longest_side();
  std::printf("\n%s, degree 2, u = 0 on the boundary, f = 1\n", title.c_str());
  std::printf("%6s %9s %7s %9s %8s %8s %8s %8s %8s %8s %8s %13s %10s %7s\n", "cells", "unknowns", "cut", "points",
              "classify", "quadr.", "assembly", "solve", "cpu s", "wall s", "peak MB", "J", "J - prev.", "ratio");
  double last_j = 0.0, last_difference = 0.0;
  for (const int n : cells_across) {
    SolverOptions options;
    options.degree = 2;
    options.cell_width = longest / n;
    options.estimate_condition = false;
    options.keep_quadrature = true;
    reset_peak();
    const auto wall = std::chrono::steady_clock::now();
    PoissonSolution<D> solution;
    try {
      solution = solve_poisson<D>(problem, options);
    } catch (const std::exception& e) {
      std::printf("%6d %s\n", n, e.what());
      continue;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
    const SolveReport& r = solution.report;
    const StageSeconds& s = r.cpu_seconds;
    const double j = integral_of_u(solution);
    std::printf("%6d %9zu %7zu %9zu %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8.0f %13.7e", n, r.unknowns, r.cells_cut,
                r.volume_points + r.surface_points, s.classification, s.quadrature, s.assembly, s.solve,
                s.total() - s.errors, seconds, peak_megabytes(), j);
    if (last_j != 0.0) std::printf(" %10.2e", j - last_j);
    if (last_difference != 0.0) std::printf(" %7.2f", last_difference / (j - last_j));
    std::printf("\n");
    std::fflush(stdout);
    last_difference = last_j != 0.0 ? j - last_j : 0.0;
    last_j = j;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "all";
  std::vector<int> cells;
  for (int i = 2; i < argc; ++i) cells.push_back(std::atoi(argv[i]));
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
  std::printf("solve_real_bench: %d thread(s); stage columns in CPU seconds\n", threads);
  if (which == "meshes" || which == "all") {
    for (const char* name : {"joint", "pinion", "bunny00"}) {
      const auto start = std::chrono::steady_clock::now();
      const geometry::Model model = geometry::load_model(shared("meshes/") + name + ".off");
      std::printf("\n%s: %zu triangles, read and validated in %.2f s\n", name, model.surface->triangles.size(),
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      refinement<3>(name, model, cells.empty() ? std::vector<int>{16, 32, 64} : cells);
    }
  }
  if (which == "lake" || which == "all") {
    const std::string path = shared("gis/lake_vanern_se_osm_EPSG32633.geojson");
    refinement<2>("Lake Vanern (718 edges, 56 islands)", geometry::load_model(path),
                  cells.empty() ? std::vector<int>{32, 64, 128, 256} : cells);
    // The whole command on one thread: read, classify, solve, write.
    const std::string problem = "/tmp/solve_real_bench_lake.json";
    std::ofstream(problem) << R"({ "domain": ")" << path << R"(", "source": 1 })";
    const std::string command = "OMP_NUM_THREADS=1 " + std::string(SAGE_BINARY_DIR) + "/cli/sage solve " + problem +
                                " -o /tmp/solve_real_bench_lake.vtu --degree 2 --cells 128";
    const auto start = std::chrono::steady_clock::now();
    const int status = std::system((command + " > /tmp/solve_real_bench_lake.txt").c_str());
    std::printf("\nsage solve lake, 128 cells, one thread, all stages with the output: %.2f s wall (exit %d)\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), status);
  }
  return 0;
}
