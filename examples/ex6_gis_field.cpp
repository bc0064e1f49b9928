//                         sage example 6: a GIS polygon to a normalized field
//
// Sample runs:  ex6_gis_field examples/models/island_with_lake.geojson island.vti
//
// Description:  What `sage field` does with GIS data: reads polygons with
//               holes and islands from a GeoJSON file (longitude/latitude,
//               projected to metres), validates them, builds the
//               well-formed CSG formula (each edge's halfplane once) and
//               samples it with value and gradient, far-field
//               approximation on. Then checks what the construction
//               promises: omega = 0 and |grad omega| = 1 at the middle of
//               every edge (the field is normalized), and the approximate
//               samples within their tolerance of exact evaluation, with
//               the same signs. Exits 1 if a check fails. Adds to example
//               4: GIS data, normalization, the far field.

#include <sage/geometry/gis_reader.hpp>
#include <sage/geometry/polygon_csg.hpp>
#include <sage/geometry/polygon_validation.hpp>
#include <sage/output/vtk_writer.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/sampling_plan.hpp>
#include <sage/tape/evaluator.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  using namespace sage;
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s POLYGONS.geojson OUT.vti\n", argv[0]);
    return 2;
  }
  try {
    // 1. Read, project and validate: rings in metres, outer rings
    //    counter-clockwise, holes clockwise.
    geometry::GisPolygons gis = geometry::read_gis_polygons(argv[1], {});
    geometry::validate_polygons(gis.polygons, argv[1]);
    std::printf("%s: %zu polygons, %zu edges; %s\n", argv[1], gis.polygons.polygons.size(), gis.polygons.edge_count(),
                gis.crs.c_str());

    // 2. The field: R0 conjunctions and disjunctions of the edges'
    //    halfplanes (polygon_csg.hpp), normalized on every edge.
    const Expr omega = geometry::polygon_csg(gis.polygons, RSystem::r0());
    const Tape tape(omega, 2);

    // 3. The promise at the middle of every edge: omega = 0, |grad| = 1.
    Evaluator<Tuple<2, 1>> exact(tape);
    double worst_value = 0, worst_gradient = 0, lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    gis.polygons.for_each_ring([&](const geometry::Ring& ring) {
      const std::size_t n = ring.points.size();
      for (std::size_t i = 0; i < n; ++i) {
        const auto& a = ring.points[i];
        const auto& b = ring.points[(i + 1) % n];
        const auto t = exact.at({0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])});
        worst_value = std::max(worst_value, std::abs(t.value()));
        worst_gradient = std::max(worst_gradient, std::abs(std::hypot(t.c[1], t.c[2]) - 1.0));
        for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], a[k]), hi[k] = std::max(hi[k], a[k]);
      }
    });
    const double diagonal = std::hypot(hi[0] - lo[0], hi[1] - lo[1]);
    std::printf("at the edges' midpoints: |omega| <= %.1e m, ||grad omega| - 1| <= %.1e\n", worst_value,
                worst_gradient);

    // 4. Sample on a 300x300 grid around the polygons as `sage field`
    //    does (plan_sampling: for a 2D R0 field, far-field patches within
    //    1e-10 of the grid box's diagonal), and compare with exact
    //    evaluation.
    Grid grid;
    grid.dimension = 2;
    grid.lo = {lo[0] - 0.05 * diagonal, lo[1] - 0.05 * diagonal, 0};
    grid.hi = {hi[0] + 0.05 * diagonal, hi[1] + 0.05 * diagonal, 0};
    grid.points = {300, 300, 1};
    const SamplingPlan plan = plan_sampling(tape, grid, 1);
    const Approximation& far_field = plan.approximation;
    std::printf("sampling: %s\n", plan.description.c_str());
    const FieldSamples samples = sample_field(tape, grid, 1, {}, &far_field);
    double worst_sample = 0;
    std::size_t wrong_signs = 0;
    for (std::size_t i = 0; i < grid.size(); i += 7) {  // every 7th point: exact evaluation is slow
      const double e = exact.at(grid.point(i)).value();
      worst_sample = std::max(worst_sample, std::abs(samples.omega[i] - e));
      wrong_signs += (e > 0) != (samples.omega[i] > 0);
    }
    std::printf("far field: samples within %.1e of exact (tolerance %.1e), %zu wrong signs\n", worst_sample,
                far_field.tolerance, wrong_signs);

    // 5. Write it for ParaView: colour by omega, contour at 0.
    output::write_field(argv[2], samples);
    std::printf("wrote %s\n", argv[2]);
    const bool normalized = worst_value <= 1e-9 * diagonal && worst_gradient <= 1e-9;
    // A coast of many edges is sampled by far-field patches by default.
    const bool patches = plan.evaluation == SamplingPlan::Evaluation::FarField;
    return patches && normalized && worst_sample <= far_field.tolerance && wrong_signs == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ex6_gis_field: %s\n", e.what());
    return 1;
  }
}
