// sage sample MODEL POINTS -o OUT.csv|.geojson|.gpkg|.shp|.fgb [--order K] [--points-crs CRS]
//             [--points-layer NAME] [--rfunction R] [--tolerance T | --exact]
//
// The field and its derivatives at places a user lists (wells, sensors,
// parcels): a CSV with x, y (and z) or lon, lat columns, or any OGR point
// layer. Points in another CRS are transformed into the plane the field
// is built in; the output keeps every input attribute and adds omega,
// grad_x, grad_y (grad_z), grad_norm and the higher partials d<k>_<xy..>.

#include "commands.hpp"
#include "field_job.hpp"

#include <sage/output/point_layer.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/sampling_plan.hpp>
#include <sage/tape/tape.hpp>

#include <boost/program_options.hpp>

#include <algorithm>
#include <iostream>
#include <stdexcept>

namespace po = boost::program_options;

namespace sage::cli {

namespace {

/// The samples as one attribute per number: omega, grad_x, ..., d2_xx, ...
/// (at most 10 characters, which Shapefiles keep whole).
std::vector<PointArray> attributes_of(const FieldSamples& s, int dimension) {
  std::vector<PointArray> arrays{{"omega", 1, s.omega}};
  if (s.gradient.empty()) return arrays;
  const std::size_t n = s.omega.size();
  for (int a = 0; a < dimension; ++a) {
    PointArray g{std::string("grad_") + "xyz"[a], 1, std::vector<double>(n)};
    for (std::size_t p = 0; p < n; ++p) g.values[p] = s.gradient[3 * p + static_cast<std::size_t>(a)];
    arrays.push_back(std::move(g));
  }
  arrays.push_back({"grad_norm", 1, s.gradient_norm});
  for (const DerivativeArray& d : s.higher) {
    const std::size_t m = d.components.size();
    for (std::size_t c = 0; c < m; ++c) {
      PointArray partial{"d" + std::to_string(d.order) + "_" + d.components[c], 1, std::vector<double>(n)};
      for (std::size_t p = 0; p < n; ++p) partial.values[p] = d.values[p * m + c];
      arrays.push_back(std::move(partial));
    }
  }
  return arrays;
}

}  // namespace

int run_sample(const std::vector<std::string>& args) {
  std::string model_path, points_path, output_path, rfunction, points_crs, points_layer;
  int order = 1;
  po::options_description options(
      "Usage: sage sample MODEL POINTS -o OUT [options]\n"
      "MODEL: a JSON model, GIS vector data or a mesh, as for sage field.\n"
      "POINTS: a CSV file with columns x and y (or lon and lat; z for 3D), or any\n"
      "point layer GDAL reads (.gpkg, .geojson, .shp, ...).\n"
      "Evaluates the model's field at every point (as sage field: far-field patches\n"
      "where they pay, --exact to forbid them) and writes the points with\n"
      "their attributes and new ones: omega, grad_x, grad_y (grad_z), grad_norm, and\n"
      "d<k>_<xy..> for --order k >= 2. OUT: .csv, .geojson, .json, .gpkg, .shp or .fgb.\n"
      "Points with a coordinate reference system (the file's or --points-crs) are\n"
      "transformed into the plane the field is built in (for longitude/latitude\n"
      "polygons, the local projection sage chose); others are taken as its coordinates.\n\n"
      "Options");
  auto add = options.add_options();
  add("help,h", "show this help");
  add("output,o", po::value(&output_path)->required(), "output file: .csv, .geojson, .json, .gpkg, .shp or .fgb");
  add("order", po::value(&order)->default_value(1), "highest derivative order written (0 to 6; 0: omega only)");
  add("points-crs", po::value(&points_crs),
      "the points' coordinate reference system, in place of the file's: EPSG:4326 for longitude/latitude, a PROJ "
      "string or WKT");
  add("points-layer", po::value(&points_layer), "the points' layer name (default: the first)");
  add("rfunction", po::value(&rfunction),
      "default R-function: minmax, r0, ralpha:A, ralpha:var, rp:P, rm:M (P, M even)");
  double tolerance = 0.0;
  add("tolerance", po::value(&tolerance),
      "far-field approximation: parts of the field far from a group of points become polynomial patches, each "
      "within this fraction of the points' bounding box's diagonal (0: exact). Default: 1e-10 for 2D R-function "
      "fields, exact otherwise (as sage field)");
  add("exact", "evaluate the whole field at every point in double precision (as --tolerance 0)");
  add("quiet,q", "no summary");
  geometry::LoadOptions load;
  SourceOptionText source_text;
  add_source_options(options, load, source_text);
  po::variables_map vm;
  if (!parse_model_command(args, options, model_path, vm, &points_path)) return 0;
  finish_source_options(vm, load, source_text);
  if (order < 0 || order > kMaxSampleOrder)
    throw UsageError{"--order must be from 0 to " + std::to_string(kMaxSampleOrder)};
  const std::optional<double> chosen = chosen_tolerance(vm, tolerance);
  output::PointLayerOptions point_options;
  if (vm.count("points-crs")) point_options.crs = points_crs;
  if (vm.count("points-layer")) point_options.layer = points_layer;

  const geometry::Model model =
      load_model(model_path, vm.count("rfunction") ? std::optional<std::string>(rfunction) : std::nullopt, load);
  const output::PointLayer layer = output::read_point_layer(points_path, model.crs_wkt, point_options);
  for (const std::string& warning : layer.warnings) std::cerr << "warning: " << warning << "\n";
  if (model.dimension == 3 && !layer.has_z)
    throw std::runtime_error(points_path + ": the model is 3D, and not every point has a z coordinate");
  const Tape tape(model.field, model.dimension);
  const SamplingPlan plan = plan_points(tape, layer.points, order, chosen);
  const FieldSamples samples = sample_points(tape, layer.points, order, &plan.approximation);
  output::write_point_layer(points_path, point_options, output_path, attributes_of(samples, model.dimension));
  if (vm.count("quiet") == 0) {
    const auto [low, high] = std::minmax_element(samples.omega.begin(), samples.omega.end());
    const auto inside = std::count_if(samples.omega.begin(), samples.omega.end(), [](double w) { return w > 0.0; });
    std::cout << "wrote " << output_path << ": " << layer.points.size() << " points (" << inside
              << " inside the domain), omega in [" << *low << ", " << *high << "]\n"
              << "coordinates: " << layer.coordinates << "\n"
              << plan.description
              << (plan.evaluation == SamplingPlan::Evaluation::Exact ? "" : "; --exact for exact evaluation") << "\n";
  }
  return 0;
}

}  // namespace sage::cli
