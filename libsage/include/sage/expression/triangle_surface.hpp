#pragma once
// TriangleSurface: the boundary of a solid as a closed, oriented triangle
// mesh (what geometry/ reads from OFF, STL, OBJ and PLY files and
// validates), for consumers that work with the triangles themselves (the
// solver's cut cells, solver/include/sage/solver/mesh_domain.hpp) rather than with a field.
//
// Conventions: closed, 2-manifold, without self-intersections; each
// triangle (a, b, c) is counter-clockwise seen from outside, so that
// (b - a) x (c - a) is the outward normal. Units are the file's.

#include <array>
#include <cstdint>
#include <vector>

namespace sage {

struct TriangleSurface {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

}  // namespace sage
