// The mesh decomposition's filtered orientation test (mesh_internal.hpp)
// against CGAL's exact predicate, on points on, near and off planes, at
// scales from 1e-95 to 1e101 and far from the origin: the same sign every
// time, and the floating-point test decides the clear cases itself.

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
  for (const double origin : {0.0, 1.0, 1e3, 1e6})
    for (const double size : {1e-95, 1e-6, 1e-2, 1.0, 1e4, 1e101})
      for (int plane = 0; plane < 20; ++plane) {
        auto point = [&] {
          return Point(origin + size * unit(rng), origin + size * unit(rng), origin + size * unit(rng));
        };
        const Point p = point(), q = point(), r = point();
        const FilteredOrientation side(p, q, r);
        const auto normal = CGAL::cross_product(q - p, r - p);
        const bool in_range = size > 1e-90 && size < 1e99 && origin < 1e-3 * size + 1e99;
        for (int k = 0; k < 200; ++k) {
          // On the plane (in doubles: off by a rounding or so), 1e-3 to
          // 1e-19 of the normal's length off it, rounded to integers, and
          // a tenth of the size off it.
          const double a = unit(rng), b = unit(rng);
          Point s = p + a * (q - p) + b * (r - p);
          if (k % 4 == 1) s = s + std::pow(10.0, -3 - k % 17) * normal;
          if (k % 4 == 2) s = Point(std::round(s.x()), std::round(s.y()), std::round(s.z()));
          if (k % 4 == 3) s = s + (0.1 * size / std::sqrt(normal.squared_length())) * normal;
          const CGAL::Orientation want = CGAL::orientation(p, q, r, s);
          ASSERT_EQ(side(s), want) << "origin " << origin << ", size " << size << ", point " << k;
          const auto decided = side.filtered(s);
          if (decided) {
            ASSERT_EQ(*decided, want) << "origin " << origin << ", size " << size << ", point " << k;
          }
          // Clearly off the plane, in range: no call to CGAL needed.
          if (k % 4 == 3 && in_range && origin <= 1e3 * size) {
            EXPECT_TRUE(decided.has_value()) << "origin " << origin << ", size " << size;
          }
        }
      }
  // Exactly coplanar: integer points on an integer plane.
  const Point p(0, 0, 0), q(1, 2, 3), r(-2, 1, 4);
  for (int i = -3; i <= 3; ++i)
    for (int j = -2; j <= 2; ++j)
      EXPECT_EQ(FilteredOrientation(p, q, r)(p + static_cast<double>(i) * (q - p) + static_cast<double>(j) * (r - p)),
                CGAL::COPLANAR);
}

}  // namespace
