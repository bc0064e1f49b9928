// sage field MODEL -o OUT.vtu|.vti|.tif [--grid 200x200 | --resolution R] [--bounds ...] [--order K]
//            [--rfunction r0] [--tolerance T | --exact] [--float64] [--crs-out EPSG:XXXX]
//            [--compression zstd|deflate|none]

#include "commands.hpp"
#include "field_job.hpp"

#include <boost/program_options.hpp>

#include <iostream>

namespace po = boost::program_options;

namespace sage::cli {

int run_field(const std::vector<std::string>& args) {
  FieldJob job;
  std::string grid, bounds, rfunction;
  po::options_description options(
      "Usage: sage field MODEL -o OUT.vtu|OUT.vti|OUT.tif [options]\n"
      "MODEL: a JSON model, GIS vector data (.geojson, .shp, .gpkg, ...) or a mesh\n"
      "(.off, .stl, .obj, .ply).\n"
      "Samples the model's field and its derivatives on a regular grid and writes\n"
      "point arrays omega, grad_omega, grad_norm (and d<k>_omega for --order k >= 2;\n"
      "omega alone for --order 0). A 2D field also goes to a GeoTIFF (.tif) for QGIS\n"
      "and GDAL: a band per component, in the coordinate system the field was built in.\n\n"
      "Options");
  auto add = options.add_options();
  add("help,h", "show this help");
  add("output,o", po::value(&job.output_path)->required(), "output file, .vtu, .vti or (2D) .tif");
  add("grid", po::value(&grid), "points per axis: 200x200 (2D, default) or 64x64x64 (3D, default)");
  double resolution = 0.0;
  add("resolution", po::value(&resolution),
      "in place of --grid: the distance between grid points (a GeoTIFF's pixel size), in the units of the "
      "model's plane (metres for longitude/latitude data, which sage projects)");
  add("float64", "GeoTIFF: Float64 bands (default Float32)");
  std::string crs_out;
  add("crs-out", po::value(&crs_out),
      "GeoTIFF: warp the raster into this CRS, e.g. EPSG:4326 (bilinear; the field is still evaluated in the plane "
      "where it was built)");
  std::string compression;
  add("compression", po::value(&compression),
      "GeoTIFF: the tiles' compression, zstd (default; GDAL 2.3 and later, so QGIS and rasterio), deflate (for "
      "readers on an older libtiff, twice as slow to write) or none");
  add("bounds", po::value(&bounds), "xmin,xmax,ymin,ymax[,zmin,zmax] (default: the model's \"bounds\")");
  add("order", po::value(&job.order)->default_value(1),
      "highest derivative order written (0 to 6; 0: omega only, for contouring)");
  add("rfunction", po::value(&rfunction),
      "default R-function: minmax, r0, ralpha:A, ralpha:var, rp:P, rm:M (P, M even)");
  double tolerance = 0.0;
  add("tolerance", po::value(&tolerance),
      "far-field approximation: parts of the field far from a grid block become polynomial patches, each within "
      "this fraction of the grid box's diagonal (0: exact). Default: 1e-10 for 2D R-function fields (R0, Rp, "
      "R_alpha), where it pays; for meshes' trimmed-face fields, far faces in single precision (the deviation "
      "measured and printed); exact otherwise");
  add("exact", "evaluate the whole field at every point in double precision (as --tolerance 0)");
  add("quiet,q", "no progress or summary");
  SourceOptionText source_text;
  add_source_options(options, job.load, source_text);
  po::variables_map vm;
  if (!parse_model_command(args, options, job.model_path, vm)) return 0;
  finish_source_options(vm, job.load, source_text);
  if (vm.count("grid")) job.grid = grid;
  if (vm.count("resolution")) job.resolution = resolution;
  job.float64 = vm.count("float64") > 0;
  if (vm.count("crs-out")) job.crs_out = crs_out;
  if (vm.count("compression")) job.compression = compression;
  if (vm.count("bounds")) job.bounds = bounds;
  if (vm.count("rfunction")) job.rfunction = rfunction;
  job.tolerance = chosen_tolerance(vm, tolerance);
  const bool quiet = vm.count("quiet") > 0;
  job.show_progress = !quiet;

  const FieldReport r = run_field_job(job);
  if (!quiet) {
    std::cout << "wrote " << job.output_path << ": " << r.grid.size() << " points (" << r.grid.points[0] << "x"
              << r.grid.points[1];
    if (r.grid.dimension == 3) std::cout << "x" << r.grid.points[2];
    std::cout << "), omega in [" << r.omega_min << ", " << r.omega_max << "], " << r.instructions
              << " tape instructions, sampling " << r.seconds_sampling << " s, writing " << r.seconds_writing << " s";
    std::cout << "\n";
    if (!r.geotiff.empty()) std::cout << r.geotiff << "\n";
    // The plan as planned, but far faces as they went: measured, or
    // rejected and sampled again exactly.
    const Approximation& a = r.plan.approximation;
    if (r.far_faces)
      std::cout << "far mesh faces in single precision (clusters farther from a batch of points than their size): "
                << "deviation from exact evaluation at most " << r.far_faces_deviation
                << " of the grid box's diagonal at " << a.far_faces_check_points
                << " grid points; --exact for exact evaluation\n";
    else if (r.far_faces_rejected)
      std::cout << "exact evaluation: far mesh faces in single precision deviated by " << r.far_faces_deviation
                << " of the grid box's diagonal (more than " << a.far_faces_limit
                << "), so the grid was sampled again\n";
    else
      std::cout << r.plan.description
                << (r.plan.evaluation == SamplingPlan::Evaluation::Exact ? "" : "; --exact for exact evaluation")
                << "\n";
  }
  return 0;
}

}  // namespace sage::cli
