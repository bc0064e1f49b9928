#pragma once
// Domains bounded by closed triangle meshes, cell by cell, from the
// triangles themselves (issue 24): no field is evaluated.
//
//  1. Binning. Each triangle goes to the cells its box overlaps and that it
//     meets (separating-axis test against the closed cell, slightly
//     enlarged): a cell's triangles are the few that can matter there.
//  2. Classification. Cells without triangles are inside or outside as a
//     whole. Each column of cells is swept upwards along one vertical line
//     (its centre, moved off the lattice by a tiny irrational offset so that
//     it meets no mesh edge): below the grid is outside, and the status
//     changes at every triangle the line crosses, to inside where the
//     triangle's outward normal points down. A cell whose triangles only
//     touch it (lie in its faces, meet it in edges or corners) counts by the
//     status at its centre, like implicit cells with a face on the lattice.
//  3. Cut cells. The triangles are clipped to the cell, coplanar ones share
//     one plane, and a binary space partition of the clipped polygons (a
//     node per plane, front leaves outside and back leaves inside) gives
//     the solid in the cell as a Boolean formula of those planes. The
//     cut-cell rule of domain_quadrature.hpp integrates it like any Boolean
//     domain: planar pieces need no root finding, the rule is exact for the
//     polynomial part, and surface points lie on the triangles with their
//     normals. A cell with more than a few distinct planes (fine meshes of
//     curved surfaces) is split in octants first, down to a limit.
//
// Membership of any point (for output) walks up its column the same way;
// the signed distance is exact within a band around the surface and
// clamped beyond it.
//
// Ownership: MeshDomain shares the surface and is read-only after
// construction; make one MeshCellQuadrature per thread.

#include <sage/expression/triangle_surface.hpp>
#include <sage/solver/background_grid.hpp>
#include <sage/solver/domain_quadrature.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace sage::solver {

class MeshDomain {
 public:
  /// Bins and classifies on all cores. Throws std::invalid_argument for an
  /// empty surface.
  MeshDomain(std::shared_ptr<const TriangleSurface> surface, const BackgroundGrid<3>& grid);

  const TriangleSurface& surface() const { return *surface_; }
  const BackgroundGrid<3>& grid() const { return grid_; }
  /// Per grid cell.
  const std::vector<CellKind>& kinds() const { return kinds_; }
  /// The triangles meeting the closed cell.
  std::span<const std::uint32_t> triangles(std::size_t cell) const;

  /// Whether p is inside the solid (points on the surface: either).
  bool inside(const std::array<double, 3>& p) const;
  /// The distance from p to the surface, positive inside, exact when it is
  /// below `band`, else +-band.
  double signed_distance(const std::array<double, 3>& p, double band) const;

 private:
  // Status just above height z on the vertical line through (x, y): the
  // first crossing above z in the column (walking up), or the status of
  // the first cell without triangles met.
  bool inside_on_line(double x, double y, double z) const;

  std::shared_ptr<const TriangleSurface> surface_;
  BackgroundGrid<3> grid_;
  std::vector<std::size_t> offset_;  // per cell: its triangles in bins_[offset_[c] .. offset_[c + 1])
  std::vector<std::uint32_t> bins_;
  std::vector<CellKind> kinds_;
};

/// Quadrature of a MeshDomain's cells; one per thread.
class MeshCellQuadrature {
 public:
  MeshCellQuadrature(const MeshDomain& domain, QuadratureOptions options);
  ~MeshCellQuadrature();
  MeshCellQuadrature(MeshCellQuadrature&&) noexcept;

  /// Appends the rule of the part of cell `cell` (box `box`) inside the
  /// solid to `volume`, and of the surface in it to `surface` when not null.
  void append_rule(std::size_t cell, const Box<3>& box, std::vector<VolumePoint<3>>& volume,
                   std::vector<SurfacePoint<3>>* surface);
  const QuadratureCounts& counts() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sage::solver
