// sage: meshfree engineering analysis with R-functions.
//
//   sage field MODEL -o OUT.vtu   sample a model's field on a grid
//   sage sample MODEL POINTS -o OUT.csv  the field at listed points
//   sage info MODEL               summarize a model
//   sage render MODEL -o OUT.png  picture of a model
//   sage demo [-o DIR]            write fields of the bundled models
//   sage solve PROBLEM -o OUT.vtu solve a boundary value problem

#include "commands.hpp"

#include <sage/geometry/cad_model.hpp>
#include <sage/geometry/csg_model.hpp>
#include <sage/output/vtk_writer.hpp>

#include <boost/program_options/errors.hpp>

#include <exception>
#include <iostream>
#include <string>
#include <vector>

#ifndef SAGE_VERSION
#define SAGE_VERSION "unknown"
#endif

namespace {

const char* kUsage =
    "Usage: sage COMMAND [options]\n"
    "\n"
    "Meshfree engineering analysis with R-functions: implicit fields with\n"
    "guaranteed differential properties, written as VTK files for ParaView.\n"
    "\n"
    "Commands:\n"
    "  field MODEL -o OUT.vtu   sample a model's field and derivatives on a grid\n"
    "  sample MODEL POINTS -o OUT.csv\n"
    "                           the field and derivatives at points (CSV, GIS layers)\n"
    "  info MODEL               summarize a model\n"
    "  render MODEL -o OUT.png  picture of a model (3D: ray cast, 2D: colour map)\n"
    "  demo [-o DIR]            write the bundled examples' fields and solutions\n"
    "  solve PROBLEM -o OUT.vtu solve a heat (Poisson) or elasticity problem\n"
    "\n"
    "Options:\n"
    "  -h, --help               show this help (sage COMMAND --help for a command)\n"
    "  --version                show the version\n";

int dispatch(const std::string& command, const std::vector<std::string>& rest) {
  if (command == "field") return sage::cli::run_field(rest);
  if (command == "sample") return sage::cli::run_sample(rest);
  if (command == "info") return sage::cli::run_info(rest);
  if (command == "render") return sage::cli::run_render(rest);
  if (command == "demo") return sage::cli::run_demo(rest);
  if (command == "solve") return sage::cli::run_solve(rest);
  std::cerr << "sage: unknown command '" << command << "'\n(see sage --help)\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
    std::cout << kUsage;
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::cout << "sage " << SAGE_VERSION << "\n"
              << "CAD files (STEP, IGES, BREP): "
              << (sage::geometry::cad_available() ? sage::geometry::cad_library() : "not built (-DSAGE_WITH_CAD=OFF)")
              << "\n";
    return 0;
  }
  const std::string command = args[0];
  try {
    return dispatch(command, std::vector<std::string>(args.begin() + 1, args.end()));
  } catch (const sage::cli::UsageError& e) {
    std::cerr << "sage " << command << ": " << e.message << "\n(see sage " << command << " --help)\n";
    return 2;
  } catch (const boost::program_options::error& e) {
    std::cerr << "sage " << command << ": " << e.what() << "\n(see sage " << command << " --help)\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "sage " << command << ": error: " << e.what() << "\n";
    return 1;
  }
}
