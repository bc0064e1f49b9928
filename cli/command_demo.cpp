// sage demo [-o DIR]: the main jobs on bundled data. Samples every bundled
// example model (some with several R-function systems, to compare; a GIS
// island among them), solves the bundled heat problems and the brackets'
// stresses (2D, and the STEP part's), and writes .vtu files for ParaView
// into DIR.

#include "commands.hpp"
#include "field_job.hpp"

#include <sage/geometry/cad_model.hpp>

#include <boost/program_options.hpp>

#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace sage::cli {

namespace {

struct DemoRun {
  const char* model;      // file in the models folder
  const char* output;     // file in the output folder
  const char* rfunction;  // nullptr: the model's own
  int order;
};

// clang-format off
const DemoRun kRuns[] = {
    {"paper004_fig9_solid.json",              "fig9_solid_r0.vtu",           nullptr,   2},
    {"paper004_fig12_halfline_simple.json",     "fig12a_halfline_simple.vtu",     nullptr, 1},
    {"paper004_fig12_halfline_normalized.json", "fig12b_halfline_normalized.vtu", nullptr, 1},
    {"paper004_fig12_halfline_smooth.json",     "fig12c_halfline_smooth.vtu",     nullptr, 2},
    {"paper004_fig13_45deg_plain.json",          "fig13a_45deg_plain.vtu",          nullptr, 1},
    {"paper004_fig13_45deg_orthogonalized.json", "fig13b_45deg_orthogonalized.vtu", nullptr, 1},
    {"plate_with_holes.json", "plate_minmax.vtu", "minmax", 1},
    {"plate_with_holes.json", "plate_r0.vtu",     "r0",     1},
    {"plate_with_holes.json", "plate_rp4.vtu",    "rp:4",   3},
    {"plate_with_holes.json", "plate_ralpha05.vtu", "ralpha:0.5", 2},
    {"primitives_3d.json",    "primitives_3d.vtu", nullptr, 1},
    {"heart_normalized.json", "heart_normalized.vtu", nullptr, 1},
    {"island_with_lake.geojson", "island_with_lake.vtu", nullptr, 1},
};
// clang-format on

// Problems solved after the fields, from the problems folder beside the
// models; the CAD bracket's when sage reads CAD files.
std::vector<const char*> demo_problems() {
  std::vector<const char*> problems = {"plate_heat.json", "block_with_hole.json", "bracket.json"};
  if (geometry::cad_available()) problems.push_back("cad_bracket_stress.json");
  return problems;
}

/// The folder of bundled models: $SAGE_DATA_DIR/models, the source tree
/// (build tree runs), or <prefix>/share/sage/models next to the program.
fs::path models_folder(const fs::path& program_folder) {
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("SAGE_DATA_DIR")) candidates.push_back(fs::path(env) / "models");
  candidates.push_back(fs::path(SAGE_SOURCE_MODELS_DIR));
  if (!program_folder.empty()) candidates.push_back(program_folder / ".." / "share" / "sage" / "models");
  for (const auto& c : candidates)
    if (fs::exists(c / kRuns[0].model)) return c;
  throw std::runtime_error("cannot find the bundled models (looked in " + candidates[0].string() + ", " +
                           candidates[1].string() + "); set SAGE_DATA_DIR to the folder holding models/");
}

}  // namespace

int run_demo(const std::vector<std::string>& args) {
  std::string out_dir = "sage-demo";
  po::options_description options(
      "Usage: sage demo [-o DIR]\n"
      "Writes fields of the bundled example models (paper 004 figures 9, 12 and 13,\n"
      "a 2D plate under four R-function systems, 3D primitives, a normalized\n"
      "formula, an island with a lake from GeoJSON), the solutions of two heat\n"
      "problems (a 2D plate, a 3D block with a cooling channel) and the stresses\n"
      "in a bolted L-bracket, in 2D and as a STEP part (displacement, stress,\n"
      "von_mises) as .vtu files for ParaView.\n\nOptions");
  options.add_options()("help,h", "show this help")("output,o", po::value(&out_dir),
                                                    "output folder (default sage-demo)");
  po::variables_map vm;
  po::store(po::command_line_parser(args).options(options).run(), vm);
  if (vm.count("help")) {
    std::cout << options << "\n";
    return 0;
  }
  po::notify(vm);

  std::error_code no_proc;  // without /proc, only the other candidates remain
  const fs::path program = fs::canonical("/proc/self/exe", no_proc);
  const fs::path models = models_folder(program.parent_path());
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw std::runtime_error(out_dir + ": cannot create the output folder: " + ec.message());

  std::cout << "sage demo: models from " << models.string() << "\n";
  for (const DemoRun& run : kRuns) {
    FieldJob job;
    job.model_path = (models / run.model).string();
    job.output_path = (fs::path(out_dir) / run.output).string();
    if (run.rfunction) job.rfunction = run.rfunction;
    job.order = run.order;
    job.show_progress = false;
    const FieldReport r = run_field_job(job);
    std::cout << "  " << std::left << std::setw(34) << run.output << std::right << std::setw(8) << r.grid.size()
              << " points, order " << run.order << ", omega in [" << std::setprecision(4) << r.omega_min << ", "
              << r.omega_max << "], " << std::setprecision(3) << r.seconds_sampling << " s\n";
  }
  const fs::path problems = models / ".." / "problems";
  const std::vector<const char*> problems_to_solve = demo_problems();
  for (const char* problem : problems_to_solve) {
    const std::string output = (fs::path(out_dir) / (fs::path(problem).stem().string() + ".vtu")).string();
    std::cout << "  solving " << problem << ":\n";
    const int status = run_solve({(problems / problem).lexically_normal().string(), "-o", output});
    if (status != 0) return status;
  }
  std::cout << "wrote " << std::size(kRuns) + problems_to_solve.size() << " files to "
            << fs::absolute(out_dir).lexically_normal().string()
            << "\nopen them in ParaView (File > Open); color fields by omega, grad_norm or d<k>_omega, "
               "solutions by u.\n";
  return 0;
}

}  // namespace sage::cli
