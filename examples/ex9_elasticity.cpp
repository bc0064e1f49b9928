//                         sage example 9: stresses around a hole
//
// Sample runs:  ex9_elasticity
//
// Description:  Kirsch's problem: a plate with a round hole of radius a,
//               pulled along x with the stress s far away. Classical
//               elasticity says the hoop stress at the top of the hole is
//               3 s, whatever the material. The quarter plate [0, 4a]^2
//               outside the hole, with symmetry rollers on its cut edges
//               and Kirsch's traction on its far edges, is solved with
//               cubic WEB-splines on three grids; the example prints
//               sigma_xx at (0, a) over s, and the largest von Mises
//               stress and where, and checks the factor 3 within 0.5%.
//               Adds to examples 5 and 8: a vector problem, rollers, and
//               stress output (what `sage solve` does with
//               "physics": "elasticity", see examples/problems/bracket.json).

#include <sage/expression/primitives.hpp>
#include <sage/solver/elasticity.hpp>

#include <cmath>
#include <cstdio>
#include <exception>

int main() {
  using namespace sage;
  using solver::ElasticPart;
  try {
    const double a = 1.0, L = 4.0, s = 1.0;

    // 1. The domain: the square minus the disk, R0-conjunction; each edge
    //    is a halfspace whose field vanishes on it (the parts' selectors).
    const RSystem r0 = RSystem::r0();
    const Expr left = halfspace({0, 0, 0}, {-1, 0, 0}, 2), bottom = halfspace({0, 0, 0}, {0, -1, 0}, 2);
    const Expr right = halfspace({L, 0, 0}, {1, 0, 0}, 2), top = halfspace({0, L, 0}, {0, 1, 0}, 2);
    solver::ElasticityProblem problem;
    problem.domain.dimension = 2;
    problem.domain.field = r_and(r_and(r_and(r_and(left, bottom, r0), right, r0), top, r0), -ball({0, 0, 0}, a, 2), r0);
    problem.domain.min = {0, 0, 0};
    problem.domain.max = {L, L, 0};
    problem.material = {200e3, 0.3, solver::PlaneMode::Stress};  // steel, MPa

    // 2. Kirsch's stress field, in polar form, turned Cartesian: the
    //    traction sigma n on the far edges (n = x on the right, y on top).
    const Expr x = Expr::x(), y = Expr::y(), r2 = square(x) + square(y);
    const Expr c2 = (square(x) - square(y)) / r2, s2 = 2.0 * x * y / r2, c = x / sqrt(r2), n = y / sqrt(r2);
    const double a2 = a * a, a4 = a2 * a2;
    const Expr srr = 0.5 * s * (1.0 - a2 / r2) + 0.5 * s * (1.0 - 4.0 * a2 / r2 + 3.0 * a4 / square(r2)) * c2;
    const Expr stt = 0.5 * s * (1.0 + a2 / r2) - 0.5 * s * (1.0 + 3.0 * a4 / square(r2)) * c2;
    const Expr srt = -0.5 * s * (1.0 + 2.0 * a2 / r2 - 3.0 * a4 / square(r2)) * s2;
    const Expr sxx = srr * square(c) + stt * square(n) - 2.0 * srt * n * c;
    const Expr syy = srr * square(n) + stt * square(c) + 2.0 * srt * n * c;
    const Expr sxy = (srr - stt) * n * c + srt * (square(c) - square(n));

    // 3. The boundary parts: rollers (one component fixed, the other free
    //    of traction) on the symmetry edges, the traction on the far
    //    edges; the hole is the rest of the boundary, traction-free.
    auto part = [](const char* name, const Expr& selector) {
      ElasticPart p;
      p.name = name;
      p.selector = selector;
      return p;
    };
    ElasticPart roller_x = part("left", left), roller_y = part("bottom", bottom);
    roller_x.displacement[0] = Expr(0.0);
    roller_y.displacement[1] = Expr(0.0);
    ElasticPart pulled_x = part("right", right), pulled_y = part("top", top);
    pulled_x.traction = {sxx, sxy, Expr(0.0)};
    pulled_y.traction = {sxy, syy, Expr(0.0)};
    pulled_x.loaded = pulled_y.loaded = true;
    problem.parts = {roller_x, roller_y, pulled_x, pulled_y};

    // 4. Solve on three grids and read the stress at the top of the hole.
    std::printf("%6s %9s %14s %14s %s\n", "cells", "unknowns", "sxx(0,a) / s", "max von Mises", "at");
    double factor = 0.0;
    for (const int cells : {8, 16, 32}) {
      solver::SolverOptions options;
      options.degree = 3;
      options.cell_width = L / cells;
      const auto solution = solver::solve_elasticity<2>(problem, options);
      solver::ElasticitySolution<2>::Probe probe(solution);
      const double top_of_hole[2] = {0.0, a};
      factor = probe.stress(top_of_hole)[0] / s;
      const auto& where = solution.report.elasticity->max_von_mises_at;
      std::printf("%6d %9zu %14.6f %14.6f (%.3f, %.3f)\n", cells, solution.report.unknowns, factor,
                  solution.report.elasticity->max_von_mises, where[0], where[1]);
    }
    // 5. The hole triples the stress: 3 within 0.5% at 32 cells.
    std::printf("stress concentration %.4f (Kirsch: 3)\n", factor);
    return std::abs(factor - 3.0) < 0.015 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ex9_elasticity: %s\n", e.what());
    return 1;
  }
}
