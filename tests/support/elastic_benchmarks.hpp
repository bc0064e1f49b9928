#pragma once
// Elasticity problems with exact solutions (elasticity.hpp), for the tests
// and bench/solve_bench (not installed): the classical solutions of Lame, Kirsch and
// Timoshenko, the thick sphere, and a linear patch test. Each problem
// carries its exact displacement; the data on its boundary come from the
// exact stress, so the discrete solution converges to it.

#include <sage/expression/primitives.hpp>
#include <sage/solver/elasticity.hpp>

#include <array>

namespace sage::solver::elastic_benchmarks {

inline Expr radius2(int dimension) {
  Expr r2 = square(Expr::x()) + square(Expr::y());
  return dimension == 3 ? r2 + square(Expr::z()) : r2;
}

/// A part fixing the listed components to the given values.
inline ElasticPart fixed_part(const std::string& name, const Expr& selector,
                              const std::array<std::optional<Expr>, 3>& values) {
  ElasticPart part;
  part.name = name;
  part.selector = selector;
  part.displacement = values;
  return part;
}

inline ElasticPart loaded_part(const std::string& name, const Expr& selector, const std::array<Expr, 3>& traction,
                               const Expr& pressure = 0.0) {
  ElasticPart part;
  part.name = name;
  part.selector = selector;
  part.traction = traction;
  part.pressure = pressure;
  part.loaded = true;
  return part;
}

/// Lame's thick-walled cylinder in plane strain: the annulus a < r < b under
/// internal pressure p, outer surface free. No displacement condition: the
/// three rigid motions are free and the pressure balances.
///     u_r = A r + B / r,  A = p a^2 (1 - 2 nu)(1 + nu) / (E (b^2 - a^2)),
///                         B = p a^2 b^2 (1 + nu) / (E (b^2 - a^2)).
inline ElasticityProblem lame_cylinder(double a = 1.0, double b = 2.0, double p = 1.0, double young = 1000.0,
                                       double nu = 0.3) {
  ElasticityProblem problem;
  problem.domain.dimension = 2;
  const RSystem r0 = RSystem::r0();
  const Expr inner = ball({0, 0, 0}, a, 2);
  problem.domain.field = r_and(ball({0, 0, 0}, b, 2), -inner, r0);
  problem.domain.min = {-b, -b, 0};
  problem.domain.max = {b, b, 0};
  problem.material = {young, nu, PlaneMode::Strain};
  problem.parts.push_back(loaded_part("inner", inner, {Expr(0.0), Expr(0.0), Expr(0.0)}, p));
  const double A = p * a * a * (1 - 2 * nu) * (1 + nu) / (young * (b * b - a * a));
  const double B = p * a * a * b * b * (1 + nu) / (young * (b * b - a * a));
  const Expr over = A + B / radius2(2);  // u_r / r
  problem.exact = std::array<Expr, 3>{over * Expr::x(), over * Expr::y(), Expr(0.0)};
  return problem;
}

/// Kirsch's plate: an infinite plate with a hole of radius a under the
/// remote tension s along x, in plane stress. Here the quarter [0, L]^2
/// outside the hole, with symmetry rollers on x = 0 (u_x = 0) and y = 0
/// (u_y = 0), the hole free, and Kirsch's traction on x = L and y = L.
/// sigma_xx = 3 s at (0, a).
inline ElasticityProblem kirsch_plate(double a = 1.0, double L = 4.0, double s = 1.0, double young = 1000.0,
                                      double nu = 0.3) {
  ElasticityProblem problem;
  problem.domain.dimension = 2;
  const RSystem r0 = RSystem::r0();
  problem.domain.field = r_and(box({0, 0, 0}, {L, L, 0}, 2, r0), -ball({0, 0, 0}, a, 2), r0);
  problem.domain.min = {0, 0, 0};
  problem.domain.max = {L, L, 0};
  problem.material = {young, nu, PlaneMode::Stress};
  const Expr x = Expr::x(), y = Expr::y(), r2 = radius2(2), r = sqrt(r2);
  const Expr c2 = (square(x) - square(y)) / r2, s2 = 2.0 * x * y / r2;
  const double a2 = a * a, a4 = a2 * a2;
  const Expr srr = 0.5 * s * (1.0 - a2 / r2) + 0.5 * s * (1.0 - 4.0 * a2 / r2 + 3.0 * a4 / square(r2)) * c2;
  const Expr stt = 0.5 * s * (1.0 + a2 / r2) - 0.5 * s * (1.0 + 3.0 * a4 / square(r2)) * c2;
  const Expr srt = -0.5 * s * (1.0 + 2.0 * a2 / r2 - 3.0 * a4 / square(r2)) * s2;
  const Expr C = x / r, S = y / r;
  const Expr sxx = srr * square(C) + stt * square(S) - 2.0 * srt * S * C;
  const Expr syy = srr * square(S) + stt * square(C) + 2.0 * srt * S * C;
  const Expr sxy = (srr - stt) * S * C + srt * (square(C) - square(S));
  problem.parts.push_back(
      fixed_part("left", halfspace({0, 0, 0}, {-1, 0, 0}, 2), {Expr(0.0), std::nullopt, std::nullopt}));
  problem.parts.push_back(
      fixed_part("bottom", halfspace({0, 0, 0}, {0, -1, 0}, 2), {std::nullopt, Expr(0.0), std::nullopt}));
  problem.parts.push_back(loaded_part("right", halfspace({L, 0, 0}, {1, 0, 0}, 2), {sxx, sxy, Expr(0.0)}));
  problem.parts.push_back(loaded_part("top", halfspace({0, L, 0}, {0, 1, 0}, 2), {sxy, syy, Expr(0.0)}));
  const double mu = problem.material.mu(), kappa = (3 - nu) / (1 + nu);
  const Expr ur = s / (4 * mu) * (r * ((kappa - 1) / 2 + c2) + a2 / r * (1.0 + (1 + kappa) * c2) - a4 / (r * r2) * c2);
  const Expr ut = s / (4 * mu) * ((1 - kappa) * a2 / r - r - a4 / (r * r2)) * s2;
  problem.exact = std::array<Expr, 3>{ur * C - ut * S, ur * S + ut * C, Expr(0.0)};
  return problem;
}

/// Timoshenko's cantilever in plane stress: [0, L] x [-c, c], the exact
/// displacement on the end x = L, the parabolic end shear of total P on
/// x = 0, the long sides free.
inline ElasticityProblem timoshenko_cantilever(double L = 4.0, double c = 0.5, double P = 1.0, double young = 1000.0,
                                               double nu = 0.3) {
  ElasticityProblem problem;
  problem.domain.dimension = 2;
  problem.domain.field = box({0, -c, 0}, {L, c, 0}, 2, RSystem::r0());
  problem.domain.min = {0, -c, 0};
  problem.domain.max = {L, c, 0};
  problem.material = {young, nu, PlaneMode::Stress};
  const Expr x = Expr::x(), y = Expr::y();
  const double I = 2.0 * c * c * c / 3.0, E = young, G = problem.material.mu();
  const Expr ux = -P * square(x) * y / (2 * E * I) - nu * P * pow_int(y, 3) / (6 * E * I) +
                  P * pow_int(y, 3) / (6 * I * G) + (P * L * L / (2 * E * I) - P * c * c / (2 * I * G)) * y;
  const Expr uy = nu * P * x * square(y) / (2 * E * I) + P * pow_int(x, 3) / (6 * E * I) - P * L * L * x / (2 * E * I) +
                  P * L * L * L / (3 * E * I);
  problem.parts.push_back(fixed_part("clamped", halfspace({L, 0, 0}, {1, 0, 0}, 2), {ux, uy, std::nullopt}));
  // sigma_xy = -P (c^2 - y^2) / (2 I); on x = 0 (normal -x) t = (-sigma_xx, -sigma_xy).
  problem.parts.push_back(loaded_part("loaded", halfspace({0, 0, 0}, {-1, 0, 0}, 2),
                                      {Expr(0.0), P * (c * c - square(y)) / (2 * I), Expr(0.0)}));
  problem.exact = std::array<Expr, 3>{ux, uy, Expr(0.0)};
  return problem;
}

/// The thick sphere a < r < b under internal pressure p:
///     u_r = A r + B / r^2,  A = p a^3 (1 - 2 nu) / (E (b^3 - a^3)),
///                           B = p a^3 b^3 (1 + nu) / (2 E (b^3 - a^3)).
/// Whole (six free rigid motions), or the octant x, y, z > 0 with
/// symmetry rollers on the coordinate planes.
inline ElasticityProblem thick_sphere(bool octant, double a = 1.0, double b = 2.0, double p = 1.0,
                                      double young = 1000.0, double nu = 0.3) {
  ElasticityProblem problem;
  problem.domain.dimension = 3;
  const RSystem r0 = RSystem::r0();
  const Expr inner = ball({0, 0, 0}, a, 3);
  problem.domain.field = r_and(ball({0, 0, 0}, b, 3), -inner, r0);
  problem.domain.min = {-b, -b, -b};
  problem.domain.max = {b, b, b};
  if (octant) {
    problem.domain.field = r_and(problem.domain.field, box({0, 0, 0}, {2 * b, 2 * b, 2 * b}, 3, r0), r0);
    problem.domain.min = {0, 0, 0};
    for (int axis = 0; axis < 3; ++axis) {
      std::array<double, 3> normal{0, 0, 0};
      normal[static_cast<std::size_t>(axis)] = -1;
      std::array<std::optional<Expr>, 3> roller{};
      roller[static_cast<std::size_t>(axis)] = Expr(0.0);
      problem.parts.push_back(fixed_part(std::string("symmetry_") + "xyz"[axis],
                                         halfspace({0, 0, 0}, {normal[0], normal[1], normal[2]}, 3), roller));
    }
  }
  problem.material = {young, nu, PlaneMode::Strain};
  problem.parts.push_back(loaded_part("inner", inner, {Expr(0.0), Expr(0.0), Expr(0.0)}, p));
  const double a3 = a * a * a, b3 = b * b * b;
  const double A = p * a3 * (1 - 2 * nu) / (young * (b3 - a3));
  const double B = p * a3 * b3 * (1 + nu) / (2 * young * (b3 - a3));
  const Expr r2 = radius2(3);
  const Expr over = A + B / (r2 * sqrt(r2));  // u_r / r
  problem.exact = std::array<Expr, 3>{over * Expr::x(), over * Expr::y(), over * Expr::z()};
  return problem;
}

}  // namespace sage::solver::elastic_benchmarks
