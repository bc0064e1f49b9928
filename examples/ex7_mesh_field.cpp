//                         sage example 7: a triangle mesh to a field
//
// Sample runs:  ex7_mesh_field l_prism.off l_prism.vti
//
// Description:  Writes a closed triangle mesh of an L-shaped prism (the
//               square [0,2]^2 less [1,2]^2, 1 high) as an OFF file, reads
//               it back as `sage field` reads meshes (CGAL validation,
//               outward orientation), and builds its CSG field by the
//               convex deficiency decomposition: the prism's convex hull
//               AND NOT the notch. Checks the field against the solid it
//               should be: the sign at 20,000 random points against the
//               L-shape's own membership test, omega = 0 and |grad omega|
//               = 1 at the centre of every face. Then samples it on a grid
//               and writes it for ParaView. Exits 1 if a check fails.
//               Adds to example 6: meshes, 3D.

#include <sage/geometry/model.hpp>
#include <sage/output/vtk_writer.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/tape/evaluator.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace {

using Point = std::array<double, 3>;

// The L-shaped outline, counter-clockwise seen from above.
const std::vector<std::array<double, 2>> kOutline = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};

bool inside_l_prism(const Point& p) {
  const bool in_square = p[0] > 0 && p[0] < 2 && p[1] > 0 && p[1] < 2 && p[2] > 0 && p[2] < 1;
  return in_square && !(p[0] > 1 && p[1] > 1);
}

/// The prism's boundary as triangles with outward orientation: bottom and
/// top fanned from the corner (0, 0) (the L is star-shaped from it), two
/// triangles per side wall.
void write_l_prism(const std::string& path) {
  const std::size_t n = kOutline.size();
  std::vector<Point> points;
  for (double z : {0.0, 1.0})
    for (const auto& c : kOutline) points.push_back({c[0], c[1], z});
  std::vector<std::array<std::size_t, 3>> faces;
  for (std::size_t i = 1; i + 1 < n; ++i) {
    faces.push_back({0, i + 1, i});          // bottom, facing -z
    faces.push_back({n, n + i, n + i + 1});  // top, facing +z
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    faces.push_back({i, j, n + j});  // walls, facing out of the counter-clockwise outline
    faces.push_back({i, n + j, n + i});
  }
  std::ofstream out(path);
  out << "OFF\n" << points.size() << " " << faces.size() << " 0\n";
  for (const Point& p : points) out << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (const auto& f : faces) out << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sage;
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s MESH.off OUT.vti\n", argv[0]);
    return 2;
  }
  try {
    // 1. The mesh file, then the model: CSG by the convex deficiency
    //    decomposition (the default method for meshes).
    write_l_prism(argv[1]);
    const geometry::Model model = geometry::load_model(argv[1]);
    for (const std::string& note : model.notes) std::printf("note: %s\n", note.c_str());
    const Tape tape(model.field, 3);
    Evaluator<Tuple<3, 1>> eval(tape);

    // 2. Signs at random points of the box around the prism.
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> coordinate(-0.25, 2.25);
    std::size_t wrong = 0;
    const int samples = 20000;
    for (int k = 0; k < samples; ++k) {
      const Point p{coordinate(random), coordinate(random), 0.5 * coordinate(random)};
      wrong += (eval.at(p).value() > 0) != inside_l_prism(p);
    }
    std::printf("signs: %zu of %d random points disagree with the L-shape\n", wrong, samples);

    // 3. Normalization at the centre of every face (walls, top, bottom).
    double worst_value = 0, worst_gradient = 0;
    auto check = [&](const Point& p) {
      const auto t = eval.at(p);
      worst_value = std::max(worst_value, std::abs(t.value()));
      worst_gradient =
          std::max(worst_gradient, std::abs(std::sqrt(t.c[1] * t.c[1] + t.c[2] * t.c[2] + t.c[3] * t.c[3]) - 1));
    };
    for (std::size_t i = 0; i < kOutline.size(); ++i) {
      const auto& a = kOutline[i];
      const auto& b = kOutline[(i + 1) % kOutline.size()];
      check({0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5});
    }
    check({0.5, 0.5, 0.0});
    check({0.5, 0.5, 1.0});
    std::printf("face centres: |omega| <= %.1e, ||grad omega| - 1| <= %.1e\n", worst_value, worst_gradient);

    // 4. Sample on a grid and write it: in ParaView, Contour at omega = 0
    //    shows the prism; grad_norm is 1 on its faces.
    Grid grid;
    grid.dimension = 3;
    grid.lo = {-0.25, -0.25, -0.25};
    grid.hi = {2.25, 2.25, 1.25};
    grid.points = {51, 51, 31};
    output::write_field(argv[2], sample_field(tape, grid, 1));
    std::printf("wrote %s\n", argv[2]);
    return wrong == 0 && worst_value <= 1e-12 && worst_gradient <= 1e-12 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ex7_mesh_field: %s\n", e.what());
    return 1;
  }
}
