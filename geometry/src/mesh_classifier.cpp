// Point membership xi(p) for a closed triangle mesh: CGAL's
// Side_of_triangle_mesh (ray casting with exact predicates) over an AABB
// tree built once, up front.
//
// Thread safety: Side_of_triangle_mesh builds its tree lazily under a
// mutex when it owns it; here the tree is built in the constructor and
// passed in, so every query only reads the tree and the mesh (the ray
// caster's random generator is a local of each call). Concurrent
// classify() and classify_box() calls are therefore safe; the test runs
// them from several threads against a single-threaded reference.
#include "mesh_internal.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Side_of_triangle_mesh.h>

#include <cmath>

namespace sage::geometry::mesh {

namespace {

using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using Traits = CGAL::AABB_traits<Kernel, Primitive>;
using Tree = CGAL::AABB_tree<Traits>;
using Side = CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel, CGAL::Default, Tree>;

class MeshClassifier final : public PointClassifier {
 public:
  MeshClassifier(const std::vector<Point>& points, const std::vector<Triangle>& triangles) {
    for (const Point& p : points) mesh_.add_vertex(p);
    using V = SurfaceMesh::Vertex_index;
    for (const Triangle& t : triangles)
      mesh_.add_face(V(static_cast<SurfaceMesh::size_type>(t[0])), V(static_cast<SurfaceMesh::size_type>(t[1])),
                     V(static_cast<SurfaceMesh::size_type>(t[2])));
    tree_.insert(faces(mesh_).first, faces(mesh_).second, mesh_);
    tree_.build();
    side_ = std::make_unique<Side>(tree_);
  }

  double classify(const double* p) const override {
    switch ((*side_)(Point(p[0], p[1], p[2]))) {
      case CGAL::ON_BOUNDED_SIDE: return 1.0;
      case CGAL::ON_BOUNDARY: return 0.0;
      case CGAL::ON_UNBOUNDED_SIDE: return -1.0;
    }
    return 0.0;
  }

  // A box that meets no triangle (the box is a solid: a triangle inside it
  // meets it) lies wholly on one side: the side of its centre.
  Interval classify_box(const Interval* box) const override {
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(box[i].lo) || !std::isfinite(box[i].hi) || box[i].lo > box[i].hi) return {-1.0, 1.0};
    const Kernel::Iso_cuboid_3 cuboid(Point(box[0].lo, box[1].lo, box[2].lo), Point(box[0].hi, box[1].hi, box[2].hi));
    if (tree_.do_intersect(cuboid)) return {-1.0, 1.0};
    const double c[3] = {box[0].mid(), box[1].mid(), box[2].mid()};
    const double side = classify(c);
    return {side, side};
  }

  int dimension() const override { return 3; }

 private:
  SurfaceMesh mesh_;
  Tree tree_;
  std::unique_ptr<Side> side_;
};

}  // namespace

std::shared_ptr<const PointClassifier> make_mesh_classifier(const std::vector<Point>& points,
                                                            const std::vector<Triangle>& triangles) {
  return std::make_shared<MeshClassifier>(points, triangles);
}

}  // namespace sage::geometry::mesh
