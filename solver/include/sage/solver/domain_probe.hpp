#pragma once
// The domain's field at points, for the solvers' output (poisson.hpp,
// elasticity.hpp): omega of an implicit domain, or, for a domain read from
// a mesh, the signed distance to its triangles, exact within
// kMeshDistanceBand cell widths of the surface and clamped to that beyond.

#include <sage/solver/mesh_domain.hpp>
#include <sage/solver/solver_options.hpp>
#include <sage/tape/evaluator.hpp>

#include <array>
#include <memory>
#include <optional>
#include <stdexcept>

namespace sage::solver {

/// One per thread.
template <int D>
class DomainProbe {
 public:
  /// `domain` for implicit domains, else `mesh` (3D).
  DomainProbe(const std::shared_ptr<const Tape>& domain, std::shared_ptr<const MeshDomain> mesh, double cell_width)
      : mesh_(std::move(mesh)), band_(kMeshDistanceBand * cell_width) {
    if (domain) field_.emplace(*domain);
  }
  double at(const double* x) {
    if constexpr (D == 3) {
      if (mesh_) return mesh_->signed_distance({x[0], x[1], x[2]}, band_);
    }
    if (!field_) throw std::logic_error("DomainProbe: neither a domain field nor a mesh");
    field_->evaluate(x);
    return field_->result();
  }

 private:
  std::shared_ptr<const MeshDomain> mesh_;
  double band_;
  std::optional<Evaluator<double>> field_;
};

}  // namespace sage::solver
