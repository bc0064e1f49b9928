// Quadrature over implicit domains: areas, moments and perimeters of disks
// and balls against closed forms, to accuracy far beyond what a
// subdivision rule reaches, and convergence of high order under refinement.
#include <sage/primitives.hpp>
#include <sage/solver/background_grid.hpp>
#include <sage/solver/domain_quadrature.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace sage::solver {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Integrals {
  double volume = 0, moment = 0, surface = 0, normal_flux = 0;
};

/// Volume, int x0^4, surface area, and int x . n over the surface.
template <int D>
Integrals integrate(const Expr& omega, std::array<double, D> lo, std::array<double, D> hi, double h, int points) {
  const DomainTapes tapes(omega, D);
  CellQuadrature<D> rule(tapes, {points, 4});
  const auto grid = BackgroundGrid<D>::covering(lo, hi, h, 1);
  Integrals sum;
  std::vector<VolumePoint<D>> volume;
  std::vector<SurfacePoint<D>> surface;
  for (std::size_t c = 0; c < grid.cell_count(); ++c) {
    Box<D> box{};
    const auto i = grid.cell_index(c);
    for (int a = 0; a < D; ++a) {
      box.lo[a] = grid.lo[a] + i[a] * h;
      box.hi[a] = box.lo[a] + h;
    }
    volume.clear();
    surface.clear();
    rule.append_rule(box, rule.classify(box), volume, &surface);
    for (const auto& p : volume) {
      sum.volume += p.weight;
      sum.moment += p.weight * std::pow(p.x[0], 4);
    }
    for (const auto& s : surface) {
      sum.surface += s.weight;
      for (int a = 0; a < D; ++a) sum.normal_flux += s.weight * s.x[a] * s.normal[a];
    }
  }
  return sum;
}

TEST(DomainQuadrature, DiskAreaMomentAndPerimeter) {
  // Off-centre so that cells are cut in general position.
  const Expr disk = ball({0.013, -0.021, 0}, 0.77, 2);
  const auto q = integrate<2>(disk, {-1, -1}, {1, 1}, 0.1, 5);
  const double r = 0.77, area = kPi * r * r;
  EXPECT_NEAR(q.volume, area, 1e-11);
  EXPECT_NEAR(q.surface, 2 * kPi * r, 1e-10);
  // int x.n dS = div(x) volume = 2 area (divergence theorem on both rules).
  EXPECT_NEAR(q.normal_flux, 2 * area, 1e-10);
  // int (x0 + c)^4 over a disk of radius r centred at -c... check against a fine rule instead.
  const auto fine = integrate<2>(disk, {-1, -1}, {1, 1}, 0.025, 8);
  EXPECT_NEAR(q.moment, fine.moment, 1e-11);
}

TEST(DomainQuadrature, ErrorFallsAtHighOrder) {
  // Area of an ellipse (not a quadric of the axes' kind the rule might favour).
  const Expr ellipse = ellipsoid({0.1, 0.05, 0}, {0.9, 0.55, 1}, 2);
  const double exact = kPi * 0.9 * 0.55;
  const double coarse = std::abs(integrate<2>(ellipse, {-1, -1}, {1, 1}, 0.1, 3).volume - exact);
  const double fine = std::abs(integrate<2>(ellipse, {-1, -1}, {1, 1}, 0.05, 3).volume - exact);
  // Gauss with 3 points per piece: order 6 at least in h; ask for 4.
  EXPECT_LT(fine, coarse / 16) << coarse << " -> " << fine;
  EXPECT_LT(fine, 1e-9);
}

TEST(DomainQuadrature, BallVolumeAndSphereArea) {
  const Expr b = ball({0.011, -0.017, 0.023}, 0.81, 3);
  const auto q = integrate<3>(b, {-1, -1, -1}, {1, 1, 1}, 0.25, 6);
  const double r = 0.81;
  EXPECT_NEAR(q.volume, 4.0 / 3 * kPi * r * r * r, 1e-8);
  EXPECT_NEAR(q.surface, 4 * kPi * r * r, 1e-7);
  EXPECT_NEAR(q.normal_flux, 3 * q.volume, 1e-7);
}

TEST(DomainQuadrature, SquareWithCornersInsideCells) {
  // Corners inside cells: subdivision isolates them, and only the few
  // sub-boxes at the corners fall back to masked Gauss points.
  const Expr square = box({-0.33, -0.41, 0}, {0.47, 0.36, 0}, 2, RSystem::r0());
  const auto q = integrate<2>(square, {-1, -1}, {1, 1}, 0.1, 3);
  // The corners' sub-boxes (h / 16) fall back to masked points: no surface points there.
  EXPECT_NEAR(q.volume, 0.8 * 0.77, 2e-5);
  EXPECT_NEAR(q.surface, 2 * (0.8 + 0.77), 8 * 0.1 / 16);
}

}  // namespace
}  // namespace sage::solver
