// sage field MODEL -o OUT.vtu [--grid 200x200] [--bounds ...] [--order K] [--rfunction r0] [--tolerance 1e-10]

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
      "Usage: sage field MODEL -o OUT.vtu|OUT.vti [options]\n"
      "MODEL: a JSON model, GIS vector data (.geojson, .shp, .gpkg, ...) or a mesh\n"
      "(.off, .stl, .obj, .ply).\n"
      "Samples the model's field and its derivatives on a regular grid and writes\n"
      "point arrays omega, grad_omega, grad_norm (and d<k>_omega for --order k >= 2).\n\n"
      "Options");
  auto add = options.add_options();
  add("help,h", "show this help");
  add("output,o", po::value(&job.output_path)->required(), "output file, .vtu or .vti");
  add("grid", po::value(&grid), "points per axis: 200x200 (2D, default) or 64x64x64 (3D, default)");
  add("bounds", po::value(&bounds), "xmin,xmax,ymin,ymax[,zmin,zmax] (default: the model's \"bounds\")");
  add("order", po::value(&job.order)->default_value(1), "highest derivative order written (1 to 6)");
  add("rfunction", po::value(&rfunction),
      "default R-function: minmax, r0, ralpha:A, ralpha:var, rp:P, rm:M (P, M even)");
  add("tolerance", po::value(&job.tolerance)->default_value(0.0, "0"),
      "far-field approximation: patches may deviate by this fraction of the\n"
      "grid box's diagonal, e.g. 1e-10 (default 0: exact; R-function fields of\n"
      "large polygons and meshes need it to be fast)");
  add("quiet,q", "no progress or summary");
  std::string where, layer;
  add_source_options(options, job.load, where, layer);
  po::variables_map vm;
  if (!parse_model_command(args, options, job.model_path, vm)) return 0;
  finish_source_options(vm, job.load, where, layer);
  if (vm.count("grid")) job.grid = grid;
  if (vm.count("bounds")) job.bounds = bounds;
  if (vm.count("rfunction")) job.rfunction = rfunction;
  const bool quiet = vm.count("quiet") > 0;
  job.show_progress = !quiet;

  const FieldReport r = run_field_job(job);
  if (!quiet) {
    std::cout << "wrote " << job.output_path << ": " << r.grid.size() << " points (" << r.grid.points[0] << "x"
              << r.grid.points[1];
    if (r.grid.dimension == 3) std::cout << "x" << r.grid.points[2];
    std::cout << "), omega in [" << r.omega_min << ", " << r.omega_max << "], " << r.instructions
              << " tape instructions, sampling " << r.seconds_sampling << " s, writing " << r.seconds_writing << " s";
    if (r.absolute_tolerance > 0)
      std::cout << ", far-field approximation with tolerance " << job.tolerance << " of the diagonal ("
                << r.absolute_tolerance << ")";
    std::cout << "\n";
  }
  return 0;
}

}  // namespace sage::cli
