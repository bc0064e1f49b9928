// Mesh domains by their triangles (mesh_domain.hpp): membership against a
// brute-force parity count, volumes and areas of polyhedra (exact where
// the faces meet sharply, close where a fine mesh of a curved surface
// bends slightly), and the solver on a cube given as a mesh: the same
// numbers as the cube's CSG field, at degree n's rates.
#include "manufactured.hpp"

#include <sage/solver/mesh_domain.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>

namespace sage::solver {
namespace {

using Vec3 = std::array<double, 3>;

/// The box of half-widths `half` about `centre`, turned by `angle` about z,
/// as 12 outward triangles.
std::shared_ptr<TriangleSurface> box_mesh(const Vec3& half, const Vec3& centre, double angle) {
  auto s = std::make_shared<TriangleSurface>();
  const double c = std::cos(angle), si = std::sin(angle);
  for (int k = 0; k < 8; ++k) {
    const Vec3 local{(k & 1 ? 1 : -1) * half[0], (k & 2 ? 1 : -1) * half[1], (k & 4 ? 1 : -1) * half[2]};
    s->points.push_back(
        {centre[0] + c * local[0] - si * local[1], centre[1] + si * local[0] + c * local[1], centre[2] + local[2]});
  }
  // Corners k = x + 2y + 4z; faces counter-clockwise seen from outside.
  s->triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                  {2, 6, 7}, {2, 7, 3}, {1, 3, 7}, {1, 7, 5}, {0, 4, 6}, {0, 6, 2}};
  return s;
}

/// The unit sphere's icosphere of `level` subdivisions (20 4^level triangles).
std::shared_ptr<TriangleSurface> icosphere(int level) {
  auto s = std::make_shared<TriangleSurface>();
  const double t = (1 + std::sqrt(5.0)) / 2;
  const Vec3 corners[12] = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  auto push = [&](Vec3 p) {
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    s->points.push_back({p[0] / n, p[1] / n, p[2] / n});
    return static_cast<std::uint32_t>(s->points.size() - 1);
  };
  for (const Vec3& p : corners) push(p);
  s->triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                  {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                  {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
    auto mid = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      const Vec3 &p = s->points[a], &q = s->points[b];
      return middle[key] = push({p[0] + q[0], p[1] + q[1], p[2] + q[2]});
    };
    std::vector<std::array<std::uint32_t, 3>> finer;
    for (const auto& [a, b, c] : s->triangles) {
      const std::uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    s->triangles = finer;
  }
  return s;
}

/// Volume and area of a closed outward mesh (divergence theorem).
std::pair<double, double> polyhedron_measures(const TriangleSurface& s) {
  double volume = 0, area = 0;
  for (const auto& [a, b, c] : s.triangles) {
    const Vec3 &p = s.points[a], &q = s.points[b], &r = s.points[c];
    const Vec3 u{q[0] - p[0], q[1] - p[1], q[2] - p[2]}, v{r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    const Vec3 n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    volume += (p[0] * n[0] + p[1] * n[1] + p[2] * n[2]) / 6;
    area += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  }
  return {volume, area};
}

/// Membership by counting crossings of a ray along a random direction.
bool parity_inside(const TriangleSurface& s, const Vec3& p, const Vec3& d) {
  int count = 0;
  for (const auto& [a, b, c] : s.triangles) {
    const Vec3 &v0 = s.points[a], &v1 = s.points[b], &v2 = s.points[c];
    const Vec3 e1{v1[0] - v0[0], v1[1] - v0[1], v1[2] - v0[2]}, e2{v2[0] - v0[0], v2[1] - v0[1], v2[2] - v0[2]};
    const Vec3 pv{d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
    const double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
    if (std::abs(det) < 1e-15) continue;
    const Vec3 tv{p[0] - v0[0], p[1] - v0[1], p[2] - v0[2]};
    const double u = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) / det;
    const Vec3 qv{tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2], tv[0] * e1[1] - tv[1] * e1[0]};
    const double v = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
    const double t = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && t > 0) ++count;
  }
  return count % 2 == 1;
}

struct Measures {
  long double volume = 0, area = 0, flux = 0;
  std::size_t cut = 0, cut_points = 0, unbroken = 0;
};

Measures integrate_mesh(const MeshDomain& domain, int points) {
  MeshCellQuadrature rule(domain, {points, points, 4, 0});
  const auto& grid = domain.grid();
  Measures m;
  std::vector<VolumePoint<3>> volume;
  std::vector<SurfacePoint<3>> surface;
  for (std::size_t c = 0; c < grid.cell_count(); ++c) {
    if (domain.kinds()[c] == CellKind::Outside) continue;
    const auto i = grid.cell_index(c);
    Box<3> box{};
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = grid.lo[a] + i[a] * grid.h;
      box.hi[a] = box.lo[a] + grid.h;
    }
    volume.clear();
    surface.clear();
    rule.append_rule(c, box, volume, &surface);
    if (domain.kinds()[c] == CellKind::Cut) {
      ++m.cut;
      m.cut_points += volume.size();
    }
    for (const auto& p : volume) m.volume += p.weight;
    for (const auto& s : surface) {
      m.area += s.weight;
      for (int a = 0; a < 3; ++a) m.flux += s.weight * s.x[a] * s.normal[a];
    }
  }
  m.unbroken = rule.counts().unbroken_boxes;
  return m;
}

TEST(MeshDomain, MembershipAgreesWithParity) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (const auto& mesh : {box_mesh({0.61, 0.47, 0.53}, {0.021, -0.013, 0.017}, 0.3), icosphere(3)}) {
    const auto grid = BackgroundGrid<3>::covering({-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, 0.2, 2);
    const MeshDomain domain(mesh, grid);
    int inside = 0;
    for (int k = 0; k < 2000; ++k) {
      const Vec3 p{u(rng), u(rng), u(rng)};
      const bool truth = parity_inside(*mesh, p, {0.3141, 0.5926, 0.7421});
      ASSERT_EQ(domain.inside(p), truth) << p[0] << " " << p[1] << " " << p[2];
      inside += truth ? 1 : 0;
      // The signed distance has the sign of membership.
      EXPECT_EQ(domain.signed_distance(p, 0.4) > 0, truth);
    }
    EXPECT_GT(inside, 100);
  }
}

TEST(MeshDomain, TurnedBoxVolumeAndAreaToRoundOff) {
  // Planes meeting at right angles: the rule with its breaks, exact.
  const auto mesh = box_mesh({0.61, 0.47, 0.53}, {0.021, -0.013, 0.017}, 0.3);
  const auto grid = BackgroundGrid<3>::covering({-1, -1, -1}, {1, 1, 1}, 0.2, 2);
  const Measures m = integrate_mesh(MeshDomain(mesh, grid), 3);
  const auto [volume, area] = polyhedron_measures(*mesh);
  EXPECT_NEAR(static_cast<double>(m.volume) / volume, 1.0, 1e-12);
  EXPECT_NEAR(static_cast<double>(m.area) / area, 1.0, 1e-12);
  EXPECT_NEAR(static_cast<double>(m.flux) / (3 * volume), 1.0, 1e-12);
  EXPECT_EQ(m.unbroken, 0u);
  EXPECT_LE(static_cast<double>(m.cut_points) / static_cast<double>(m.cut), 8.0 * 27);
}

TEST(MeshDomain, SolidFillingTheGridToItsTop) {
  // The box is the grid: its top face lies on the grid's top, and the
  // columns along its vertical edges hold only triangles that touch their
  // cells. Membership there walks up to the top face, which must count.
  const auto mesh = box_mesh({1, 1, 0.5}, {0, 0, 0.5}, 0.0);
  const auto grid = BackgroundGrid<3>::covering({-1, -1, 0}, {1, 1, 1}, 0.1, 2);
  const MeshDomain domain(mesh, grid);
  for (const double z : {0.05, 0.55, 0.95}) {
    EXPECT_TRUE(domain.inside({0.95, 0.95, z})) << z;
    EXPECT_TRUE(domain.inside({-0.95, 0.05, z})) << z;
  }
  EXPECT_FALSE(domain.inside({0.5, 0.5, 1.05}));
  const Measures m = integrate_mesh(domain, 3);
  EXPECT_NEAR(static_cast<double>(m.volume), 4.0, 1e-12);
  EXPECT_NEAR(static_cast<double>(m.area), 16.0, 1e-12);
}

TEST(MeshDomain, FineSphereMeshVolumeAndArea) {
  // 5,120 facets, a few per cell: their bends are slight, and the cells
  // take lines over unbroken bases. The area is exact (the polygons' own
  // rules); the volume misses the kinks of the lines' integrals across
  // the bends (5e-5 with 5 facets per cell), less as the cells hold fewer.
  const auto mesh = icosphere(4);
  const auto [volume, area] = polyhedron_measures(*mesh);
  double last = 1.0;
  for (const int cells : {13, 26}) {
    const auto grid = BackgroundGrid<3>::covering({-1, -1, -1}, {1, 1, 1}, 2.0 / cells, 2);
    const Measures m = integrate_mesh(MeshDomain(mesh, grid), 3);
    const double error = std::abs(static_cast<double>(m.volume) / volume - 1);
    std::printf("  icosphere, %d cells: %zu cut (%zu unbroken), volume error %.2e, area error %.2e\n", cells, m.cut,
                m.unbroken, error, static_cast<double>(m.area) / area - 1);
    EXPECT_GT(m.unbroken, 0u);
    EXPECT_NEAR(static_cast<double>(m.area) / area, 1.0, 1e-12);
    EXPECT_LT(error, 1e-4);
    EXPECT_LT(error, last / 1.5);  // first order: the bends cut fewer cells
    last = error;
  }
}

TEST(MeshDomain, CubeMeshSolvesLikeItsField) {
  // The cube as 12 triangles against the cube's CSG field: the same rule
  // points, so the same errors; and degree n's rates.
  using namespace manufactured;
  for (const int degree : {2, 3}) {
    PoissonProblem field = dirichlet_box(3), mesh = field;
    mesh.domain.boundary_mesh = box_mesh({1, 1, 1}, {0, 0, 0}, 0.0);
    SolverOptions options;
    options.degree = degree;
    options.estimate_condition = false;
    options.cg_tolerance = 1e-12;  // the two rules' sums differ in order: solve both to round-off
    std::vector<RefinementRun> runs;
    for (const int cells : {5, 11}) {
      options.cell_width = 2.0 / cells;
      runs.push_back({options.cell_width, solve_poisson<3>(mesh, options).report});
      const SolveReport csg = solve_poisson<3>(field, options).report;
      EXPECT_NEAR(l2(runs.back().report) / l2(csg), 1.0, 1e-6) << cells << " cells";  // threads sum in any order
      EXPECT_EQ(runs.back().report.volume_points, csg.volume_points);
    }
    std::printf("  cube mesh, degree %d: L2 %.3e -> %.3e, H1 %.3e -> %.3e\n", degree, l2(runs[0].report),
                l2(runs[1].report), h1(runs[0].report), h1(runs[1].report));
    EXPECT_GE(last_rate(runs, l2), degree + 1 - 0.3);
    EXPECT_GE(last_rate(runs, h1), degree - 0.3);
  }
}

}  // namespace
}  // namespace sage::solver
