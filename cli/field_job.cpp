#include "field_job.hpp"

#include "commands.hpp"
#include "progress.hpp"

#include <sage/output/geotiff_writer.hpp>
#include <sage/output/output_file.hpp>
#include <sage/output/vtk_writer.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/tape/tape.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace sage::cli {

namespace {
double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// What a GeoTIFF holds, in words, for the summary.
std::string describe_geotiff(const FieldSamples& samples, const geometry::Model& model,
                             const output::GeoTiffOptions& options, const output::GeoTiffLayout& layout) {
  std::ostringstream text;
  const std::vector<std::string> bands = output::geotiff_band_names(samples);
  text << "GeoTIFF: " << bands.size() << (options.float64 ? " Float64" : " Float32") << " band(s)";
  for (std::size_t b = 0; b < bands.size(); ++b) text << (b ? ", " : " ") << bands[b];
  auto name = [](const std::string& wkt) {
    const std::string n = output::crs_name(wkt);
    return n.empty() ? std::string("(unnamed)") : n;
  };
  if (model.crs_wkt.empty())
    text << "; pixels " << samples.grid.spacing(0) << " x " << samples.grid.spacing(1)
         << " centred on the grid points; no coordinate reference system: " << model.source
         << " has none (coordinates written as they are)";
  else if (options.warp_to_wkt.empty())
    text << "; pixels " << samples.grid.spacing(0) << " x " << samples.grid.spacing(1)
         << " centred on the grid points; coordinate reference system " << name(model.crs_wkt)
         << ", where the field was built";
  else
    text << "; warped (bilinear) into " << name(options.warp_to_wkt) << ": the field was evaluated in the plane where "
         << "it was built, " << name(model.crs_wkt) << ", and resampled; grad_omega_x, _y are that plane's components";
  text << "; " << layout.width << " x " << layout.height << " pixels in 512-pixel "
       << output::compression_name(options.compression) << " tiles, ";
  if (layout.overview_levels > 0)
    text << layout.overview_levels << " overview level(s)";
  else
    text << "no overviews (none under " << output::geotiff_overview_side << " pixels a side)";
  return text.str();
}

/// --compression, checked before the work.
output::GeoTiffCompression compression_of(const FieldJob& job, bool geotiff) {
  if (!job.compression) return output::GeoTiffCompression::zstd;
  if (!geotiff) throw UsageError{"--compression is for GeoTIFF output (.tif)"};
  using output::GeoTiffCompression;
  const std::pair<const char*, GeoTiffCompression> names[] = {
      {"zstd", GeoTiffCompression::zstd}, {"deflate", GeoTiffCompression::deflate}, {"none", GeoTiffCompression::none}};
  for (const auto& [name, compression] : names)
    if (*job.compression == name) return compression;
  throw UsageError{"--compression " + *job.compression + ": use zstd, deflate or none"};
}

/// --crs-out as WKT, checked before the work (a usage error when unknown).
std::string warp_target(const FieldJob& job, bool geotiff) {
  if (!job.crs_out) return "";
  if (!geotiff) throw UsageError{"--crs-out is for GeoTIFF output (.tif)"};
  try {
    return output::crs_wkt_from(*job.crs_out);
  } catch (const output::OutputError& e) {
    throw UsageError{std::string("--crs-out ") + e.what()};
  }
}
}  // namespace

geometry::Model load_model(const std::string& path, const std::optional<std::string>& rfunction,
                           geometry::LoadOptions options) {
  if (rfunction) {
    try {
      options.rfunction = RSystem::parse(*rfunction);
    } catch (const std::invalid_argument& e) {
      throw UsageError{std::string("--rfunction: ") + e.what()};
    }
  }
  if (options.method != "csg" && options.method != "brep")
    throw UsageError{"--method must be csg or brep, not '" + options.method + "'"};
  geometry::Model model = geometry::load_model(path, options);
  for (const std::string& warning : model.warnings) std::cerr << "warning: " << warning << "\n";
  return model;
}

void add_source_options(boost::program_options::options_description& description, geometry::LoadOptions& options,
                        SourceOptionText& text) {
  namespace po = boost::program_options;
  auto add = description.add_options();
  add("method", po::value(&options.method)->default_value("csg"),
      "polygons and meshes: csg (well-formed CSG) or brep (trimmed edges/faces)");
  add("feature", po::value(&options.features)->multitoken(), "GIS: feature numbers to use (0-based; repeatable)");
  add("where", po::value(&text.where), "GIS: attribute filter, e.g. \"NAME = 'Wisconsin'\"");
  add("layer", po::value(&text.layer), "GIS: layer name (default: the first)");
  add("crs", po::value(&text.crs),
      "GIS: the data's coordinate reference system, e.g. EPSG:4326 (any CRS PROJ knows),\n"
      "in place of the file's own or for files without one");
  add("repair", po::bool_switch(&options.repair), "fix invalid geometry (GEOS MakeValid, in the projected plane)");
  add("orthogonalize", po::bool_switch(&options.orthogonalize), "B-rep: orthogonalize trimming at corners");
  add("solid", po::value(&text.solid), "CAD: the solid to use, numbered from 1 (default: all, united)");
  add("deflection", po::value(&text.deflection),
      "CAD: the tessellation's chordal deflection, in the file's unit\n(default: 1e-3 of the bounding box's diagonal)");
}

bool parse_model_command(const std::vector<std::string>& args,
                         const boost::program_options::options_description& options, std::string& model_path,
                         boost::program_options::variables_map& vm, std::string* points_path) {
  namespace po = boost::program_options;
  po::options_description hidden;
  hidden.add_options()("model", po::value(&model_path)->required());
  if (points_path) hidden.add_options()("points", po::value(points_path)->required());
  po::options_description all;
  all.add(options).add(hidden);
  po::positional_options_description positional;
  positional.add("model", 1);
  if (points_path) positional.add("points", 1);
  po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
  if (vm.count("help")) {
    std::cout << options << "\n";
    return false;
  }
  po::notify(vm);
  return true;
}

namespace {
/// A far-field tolerance users may ask for: from 0 (exact) to below 1e-2 of the diagonal.
void check_tolerance(double tolerance) {
  if (!(tolerance >= 0 && tolerance < 1e-2))
    throw UsageError{"--tolerance must be from 0 (exact, as --exact) to below 1e-2 of the diagonal"};
}
}  // namespace

std::optional<double> chosen_tolerance(const boost::program_options::variables_map& vm, double tolerance) {
  if (vm.count("exact") && vm.count("tolerance")) throw UsageError{"give --exact or --tolerance, not both"};
  if (vm.count("exact")) return 0.0;
  if (!vm.count("tolerance")) return std::nullopt;
  check_tolerance(tolerance);
  return tolerance;
}

void finish_source_options(const boost::program_options::variables_map& vm, geometry::LoadOptions& options,
                           const SourceOptionText& text) {
  if (vm.count("where")) options.where = text.where;
  if (vm.count("layer")) options.layer = text.layer;
  if (vm.count("crs")) options.crs = text.crs;
  if (vm.count("solid")) {
    if (text.solid < 1) throw UsageError{"--solid numbers solids from 1"};
    options.solid = text.solid;
  }
  if (vm.count("deflection")) {
    if (!(text.deflection > 0 && std::isfinite(text.deflection)))
      throw UsageError{"--deflection must be a positive length"};
    options.deflection = text.deflection;
  }
}

Grid grid_for(const geometry::Model& model, const std::optional<std::string>& resolution,
              const std::optional<std::string>& bounds, std::optional<double> spacing) {
  Grid grid;
  grid.dimension = model.dimension;
  try {
    grid.points =
        resolution ? Grid::parse_resolution(*resolution, model.dimension) : Grid::default_points(model.dimension);
    if (bounds) {
      Grid::parse_bounds(*bounds, model.dimension, grid.lo, grid.hi);
    } else if (model.bounds) {
      grid.lo = model.bounds->min;
      grid.hi = model.bounds->max;
    } else {
      throw UsageError{model.source + " has no \"bounds\": give --bounds xmin,xmax,ymin,ymax" +
                       (model.dimension == 3 ? ",zmin,zmax" : "")};
    }
  } catch (const std::invalid_argument& e) {
    throw UsageError{e.what()};
  }
  if (model.dimension == 2) grid.lo[2] = grid.hi[2] = 0.0;
  if (spacing) {
    try {
      grid.space_points(*spacing);
    } catch (const std::invalid_argument& e) {
      throw UsageError{std::string("--resolution ") + e.what()};
    }
  }
  return grid;
}

FieldReport run_field_job(const FieldJob& job) {
  const bool geotiff = output::is_geotiff_path(job.output_path);
  if (!geotiff && !output::is_supported_field_path(job.output_path))
    throw UsageError{"-o " + job.output_path + ": the output must end in .vtu, .vti or .tif"};
  if (job.float64 && !geotiff) throw UsageError{"--float64 is for GeoTIFF output (.tif): .vtu and .vti hold doubles"};
  if (job.grid && job.resolution) throw UsageError{"give --grid or --resolution, not both"};
  const output::GeoTiffOptions tiff_options{"", job.float64, warp_target(job, geotiff), compression_of(job, geotiff)};
  if (job.order < 0 || job.order > kMaxSampleOrder)
    throw UsageError{"--order must be from 0 to " + std::to_string(kMaxSampleOrder)};
  if (job.tolerance) check_tolerance(*job.tolerance);
  output::check_writable(job.output_path);  // before the work, not after it
  const geometry::Model model = load_model(job.model_path, job.rfunction, job.load);
  if (geotiff && model.dimension != 2)
    throw UsageError{"-o " + job.output_path + ": a GeoTIFF holds 2D fields, and " + job.model_path +
                     " is 3D: write .vti or .vtu"};
  if (job.crs_out && model.crs_wkt.empty())
    throw UsageError{"--crs-out: " + job.model_path +
                     " has no coordinate reference system to warp from (GIS data without one: give --crs)"};
  FieldReport report;
  report.grid = grid_for(model, job.grid, job.bounds, job.resolution);

  auto start = std::chrono::steady_clock::now();
  const Tape tape(model.field, model.dimension);
  report.instructions = tape.code().size();
  report.plan = plan_sampling(tape, report.grid, job.order, job.tolerance);
  const FieldSamples samples = sample_field(
      tape, report.grid, job.order, job.show_progress ? terminal_progress("sampling " + job.model_path) : Progress{},
      &report.plan.approximation);
  report.seconds_sampling = seconds_since(start);
  report.far_faces = samples.far_faces;
  report.far_faces_rejected = samples.far_faces_rejected;
  report.far_faces_deviation = samples.far_faces_deviation;
  const auto [lo, hi] = std::minmax_element(samples.omega.begin(), samples.omega.end());
  report.omega_min = *lo;
  report.omega_max = *hi;
  auto finite_at = [&samples](std::size_t i) {
    if (!std::isfinite(samples.omega[i])) return false;
    if (!samples.gradient_norm.empty() && !std::isfinite(samples.gradient_norm[i])) return false;
    for (const DerivativeArray& d : samples.higher) {
      const std::size_t m = d.components.size();
      for (std::size_t c = 0; c < m; ++c)
        if (!std::isfinite(d.values[i * m + c])) return false;
    }
    return true;
  };
  for (std::size_t i = 0; i < samples.omega.size(); ++i)
    if (!finite_at(i)) {
      const auto p = report.grid.point(i);
      throw std::runtime_error(job.model_path + ": the field or one of its derivatives is not finite at grid point (" +
                               std::to_string(p[0]) + ", " + std::to_string(p[1]) +
                               (model.dimension == 3 ? ", " + std::to_string(p[2]) : std::string()) +
                               "): a pole, or a formula outside its domain (sqrt or log of a negative number)");
    }

  start = std::chrono::steady_clock::now();
  if (geotiff) {
    output::GeoTiffOptions options = tiff_options;
    options.crs_wkt = model.crs_wkt;
    const output::GeoTiffLayout layout = output::write_geotiff(job.output_path, samples, options);
    report.geotiff = describe_geotiff(samples, model, options, layout);
  } else {
    output::write_field(job.output_path, samples);
  }
  report.seconds_writing = seconds_since(start);
  return report;
}

}  // namespace sage::cli
