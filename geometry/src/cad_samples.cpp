// Sample points for the exact CAD field (cad_samples.hpp).
#include "mesh_internal.hpp"  // CGAL's headers before OCCT's (OCCT's Handle macro)

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include "cad_samples.hpp"

#include <BRepClass3d_SolidClassifier.hxx>

#include <limits>
#include <map>
#include <random>

namespace sage::geometry::cad {

namespace {

/// Distance to the tessellation (CGAL's AABB tree).
class TessellationDistance {
 public:
  explicit TessellationDistance(const TriangleSurface& surface) {
    const auto at = [&](std::uint32_t i) {
      return mesh::Point(surface.points[i][0], surface.points[i][1], surface.points[i][2]);
    };
    for (const auto& t : surface.triangles) triangles_.emplace_back(at(t[0]), at(t[1]), at(t[2]));
    if (triangles_.empty()) return;
    tree_.insert(triangles_.begin(), triangles_.end());
    tree_.accelerate_distance_queries();
  }
  /// Infinite when there is no triangle.
  double operator()(const Vec3& p) const {
    if (triangles_.empty()) return std::numeric_limits<double>::infinity();
    return std::sqrt(tree_.squared_distance(mesh::Point(p[0], p[1], p[2])));
  }

 private:
  using Triangles = std::vector<mesh::Kernel::Triangle_3>;
  using Tree = CGAL::AABB_tree<
      CGAL::AABB_traits<mesh::Kernel, CGAL::AABB_triangle_primitive<mesh::Kernel, Triangles::iterator>>>;
  Triangles triangles_;
  Tree tree_;
};

}  // namespace

struct Membership::Impl {
  BRepClass3d_SolidClassifier classifier;
  double scale, tolerance, margin;
  TessellationDistance boundary, curved;
  std::shared_ptr<const PointClassifier> mesh;
};

Membership::Membership(const TopoDS_Shape& shape, double scale, double tolerance, const TriangleSurface& tessellation,
                       const TriangleSurface& curved, double margin)
    : impl_(new Impl{BRepClass3d_SolidClassifier(shape), scale, tolerance, margin, TessellationDistance(tessellation),
                     TessellationDistance(curved), nullptr}) {
  std::vector<mesh::Point> points;
  for (const auto& p : tessellation.points) points.emplace_back(p[0], p[1], p[2]);
  std::vector<mesh::Triangle> triangles;
  for (const auto& t : tessellation.triangles) triangles.push_back({t[0], t[1], t[2]});
  impl_->mesh = mesh::make_mesh_classifier(points, triangles);
}

Membership::~Membership() = default;

bool Membership::off_boundary(const Vec3& p) const { return impl_->boundary(p) > impl_->margin; }

int Membership::operator()(const Vec3& p) {
  // Planar faces' triangles are exact; the tessellated solid differs from
  // the exact one only within the deflection of the curved faces'.
  if (impl_->curved(p) > impl_->margin) return static_cast<int>(impl_->mesh->classify(p.data()));
  impl_->classifier.Perform(gp_Pnt(p[0] * impl_->scale, p[1] * impl_->scale, p[2] * impl_->scale), impl_->tolerance);
  switch (impl_->classifier.State()) {
    case TopAbs_IN: return 1;
    case TopAbs_OUT: return -1;
    default: return 0;
  }
}

std::vector<Sample> samples(const Vec3& lo, const Vec3& hi, int n, const TriangleSurface& surface,
                            const std::vector<double>& offsets, std::size_t max_triangles, std::uint32_t seed,
                            Membership& membership) {
  std::vector<Vec3> points;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const int index[3] = {i, j, k};
        Vec3 p;
        for (std::size_t a = 0; a < 3; ++a) p[a] = lo[a] + (hi[a] - lo[a]) * (index[a] + unit(random)) / n;
        points.push_back(p);
      }
  const std::size_t stride = surface.triangles.size() / max_triangles + 1;
  for (std::size_t i = 0; i < surface.triangles.size(); i += stride) {
    const auto& t = surface.triangles[i];
    const Vec3 &a = surface.points[t[0]], &b = surface.points[t[1]], &c = surface.points[t[2]];
    Vec3 normal = cross(minus(b, a), minus(c, a));
    const double length = norm(normal);
    if (length == 0) continue;
    for (double& x : normal) x /= length;
    const Vec3 centroid{(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3};
    for (double offset : offsets)
      for (double sense : {-1.0, 1.0})
        points.push_back({centroid[0] + sense * offset * normal[0], centroid[1] + sense * offset * normal[1],
                          centroid[2] + sense * offset * normal[2]});
  }
  std::vector<Sample> out;
  for (const Vec3& p : points)
    if (const int side = membership(p)) out.push_back({p, side});
  return out;
}

/// Sorts samples into the inside and outside sign vectors; a vector seen
/// on both sides is returned in `conflict` (its first point).
void sign_vectors(const std::vector<Sample>& points, SignsAt& signs, std::vector<SignVector>& inside,
                  std::vector<SignVector>& outside, std::optional<Vec3>& conflict) {
  std::map<SignVector, std::pair<int, Vec3>> seen;
  conflict.reset();
  for (const Sample& s : points) {
    SignVector v = signs(s.p);
    if (v.empty()) continue;
    const auto [it, fresh] = seen.emplace(std::move(v), std::make_pair(s.side, s.p));
    if (!fresh && it->second.first != s.side && !conflict) conflict = s.p;
  }
  inside.clear(), outside.clear();
  for (const auto& [v, side] : seen) (side.first > 0 ? inside : outside).push_back(v);
}

}  // namespace sage::geometry::cad
