// sage info MODEL [--rfunction r0]: what a model holds, without sampling it.

#include "commands.hpp"
#include "field_job.hpp"

#include <sage/geometry/cad_model.hpp>
#include <sage/output/output_file.hpp>
#include <sage/output/vtk_writer.hpp>

#include <sage/sampling/sampling_plan.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <boost/program_options.hpp>

#include <iostream>

namespace po = boost::program_options;

namespace sage::cli {

int run_info(const std::vector<std::string>& args) {
  std::string model_path, rfunction;
  po::options_description options("Usage: sage info MODEL [options]\nPrints a summary of a model.\n\nOptions");
  geometry::LoadOptions load;
  SourceOptionText source_text;
  auto add = options.add_options();
  add("help,h", "show this help");
  add("rfunction", po::value(&rfunction), "default R-function (as for sage field)");
  add("no-certify", "polygons: skip the well-formedness certificate");
  std::string faces_vtp;
  add("faces-vtp", po::value(&faces_vtp),
      "CAD: also write the tessellated faces to this .vtp, cell array `face`\n(colour by it in ParaView to pick "
      "parts)");
  add_source_options(options, load, source_text);
  po::variables_map vm;
  if (!parse_model_command(args, options, model_path, vm)) return 0;
  finish_source_options(vm, load, source_text);
  load.certify = vm.count("no-certify") == 0;
  if (vm.count("faces-vtp")) {
    if (!faces_vtp.ends_with(".vtp")) throw UsageError{"--faces-vtp writes a .vtp file"};
    output::check_writable(faces_vtp);
  }

  const geometry::Model model =
      load_model(model_path, vm.count("rfunction") ? std::optional<std::string>(rfunction) : std::nullopt, load);
  const Tape tape(model.field, model.dimension);
  std::cout << "model:       " << model_path << (model.name.empty() ? "" : " (" + model.name + ")") << "\n"
            << "dimension:   " << model.dimension << "\n"
            << "R-function:  " << model.rfunction.name() << " (default for operators)\n";
  if (model.faces.empty()) std::cout << "primitives:  " << model.primitives.size() << "\n";  // CAD: faces below
  for (const auto& p : model.primitives)
    std::cout << "  " << p.type << (p.name.empty() ? "" : " \"" + p.name + "\"") << " at " << p.pointer << "\n";
  for (const auto& note : model.notes) std::cout << "note:        " << note << "\n";
  if (!model.faces.empty()) {
    std::cout << "faces:       " << model.faces.size() << " (number, surface, parameters, area, centroid; in "
              << model.unit << "): a problem file names them as parts, \"face:N\" or \"faces\"\n";
    for (std::size_t f = 1; f <= model.faces.size(); ++f)
      std::cout << "  " << geometry::describe_face(model, f) << "\n";
  }
  if (vm.count("faces-vtp")) {
    if (model.faces.empty())
      throw std::runtime_error(model_path + ": --faces-vtp: the model has no faces (CAD files have them)");
    output::write_surface(faces_vtp, *model.surface,
                          {{"face", std::vector<int>(model.triangle_faces.begin(), model.triangle_faces.end())}});
    std::cout << "wrote " << faces_vtp << ": " << model.surface->triangles.size() << " triangles, cell array face (1.."
              << model.faces.size() << ")\n";
  }
  std::cout << "expression:  " << model.field.node_count() << " nodes, tape of " << tape.code().size()
            << " instructions over " << tape.register_count() << " registers\n";
  if (model.bounds) {
    const auto& b = *model.bounds;
    std::cout << "bounds:      [" << b.min[0] << ", " << b.max[0] << "] x [" << b.min[1] << ", " << b.max[1] << "]";
    if (model.dimension == 3) std::cout << " x [" << b.min[2] << ", " << b.max[2] << "]";
    std::cout << "\n";
    Interval box[3] = {{b.min[0], b.max[0]}, {b.min[1], b.max[1]}, {b.min[2], b.max[2]}};
    Evaluator<Interval> eval(tape);
    eval.evaluate_with(box);
    std::cout << "omega range: within [" << eval.result().lo << ", " << eval.result().hi
              << "] over the bounds (interval arithmetic)\n";
    const SamplingPlan plan = plan_sampling(tape, grid_for(model, std::nullopt, std::nullopt), FieldJob{}.order);
    std::cout << "sampling:    sage field by default: " << plan.description
              << (plan.evaluation == SamplingPlan::Evaluation::Exact ? "" : "; --exact for exact evaluation") << "\n";
  } else {
    std::cout << "bounds:      none in the model (sage field needs --bounds)\n";
  }
  return 0;
}

}  // namespace sage::cli
