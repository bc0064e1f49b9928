// The mesh decomposition's filtered orientation test (mesh_internal.hpp)
// against CGAL's exact predicate, on points on, near and far from planes,
// at several scales and far from the origin: the same sign every time.

#include "../../geometry/src/mesh_internal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

using sage::geometry::mesh::FilteredOrientation;
using sage::geometry::mesh::Point;

TEST(MeshOrientation, FilteredSignsAreCgalsOnAndNearPlanes) {
  std::mt19937_64 rng(20261206);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::size_t tested = 0;
  for (const double origin : {0.0, 1.0, 1e3, 1e6})
    for (const double size : {1e-6, 1e-2, 1.0, 1e4})
      for (int plane = 0; plane < 20; ++plane) {
        auto point = [&] {
          return Point(origin + size * unit(rng), origin + size * unit(rng), origin + size * unit(rng));
        };
        const Point p = point(), q = point(), r = point();
        const FilteredOrientation side(p, q, r);
        const auto normal = CGAL::cross_product(q - p, r - p);
        for (int k = 0; k < 200; ++k) {
          // On the plane (in doubles: off by a rounding or so), 1e-3 to
          // 1e-19 of the normal's length off it, and rounded to integers.
          const double a = unit(rng), b = unit(rng);
          Point s = p + a * (q - p) + b * (r - p);
          if (k % 4 == 1) s = s + std::pow(10.0, -3 - k % 17) * normal;
          if (k % 4 == 2) s = Point(std::round(s.x()), std::round(s.y()), std::round(s.z()));
          const CGAL::Orientation want = CGAL::orientation(p, q, r, s);
          ++tested;
          ASSERT_EQ(side(s), want) << "origin " << origin << ", size " << size << ", point " << k;
        }
      }
  // Integer points on integer planes: exactly coplanar cases.
  for (int k = 0; k < 200; ++k) {
    const Point p(0, 0, 0), q(1, 2, 3), r(-2, 1, 4);
    const Point s = p + static_cast<double>(k % 7) * (q - p) + static_cast<double>(k % 5 - 2) * (r - p);
    EXPECT_EQ(FilteredOrientation(p, q, r)(s), CGAL::COPLANAR);
  }
  EXPECT_EQ(tested, 4u * 4u * 20u * 200u);
}

}  // namespace
