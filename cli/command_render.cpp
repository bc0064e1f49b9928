// sage render MODEL -o OUT.png [--size 800x600] [--camera ...] [--light ...]
//   [--shadows] [--hit interval|sphere] [--bounds ...] [--materials]

#include "commands.hpp"
#include "field_job.hpp"

#include <sage/output/output_file.hpp>
#include <sage/output/png_writer.hpp>
#include <sage/render/field_map.hpp>
#include <sage/render/solid.hpp>
#include <sage/sampling/grid.hpp>

#include <boost/program_options.hpp>

#include <iostream>
#include <stdexcept>

namespace po = boost::program_options;

namespace sage::cli {

namespace {

void parse_size(const std::string& text, int& width, int& height) {
  const auto x = text.find('x');
  try {
    std::size_t used_w = 0, used_h = 0;
    width = std::stoi(text.substr(0, x), &used_w);
    height = std::stoi(text.substr(x + 1), &used_h);
    if (x == std::string::npos || used_w != x || used_h != text.size() - x - 1) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw UsageError{"--size: expected WIDTHxHEIGHT, e.g. 800x600, not \"" + text + "\""};
  }
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw UsageError{"--size: width and height must be 1 to 16384"};
}

/// Fails before the (possibly long) render if the picture cannot be written.
void check_output(const std::string& path) {
  if (path.size() < 4 || path.compare(path.size() - 4, 4, ".png") != 0)
    throw UsageError{"-o " + path + ": the output must end in .png"};
  output::check_writable(path);
}

template <class F>
auto usage_checked(F&& f) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw UsageError{e.what()};
  }
}

}  // namespace

int run_render(const std::vector<std::string>& args) {
  std::string model_path, output_path, size = "800x600", camera, light, hit = "interval", bounds, rfunction;
  po::options_description options(
      "Usage: sage render MODEL -o OUT.png [options]\n"
      "3D models: ray casting by interval bisection (or sphere tracing with\n"
      "Lipschitz bounds from interval gradients), shaded with exact normals.\n"
      "2D models: a colour map (red inside, blue outside) with isolines and the\n"
      "zero contour in bold.\n\n"
      "Options");
  auto add = options.add_options();
  add("help,h", "show this help");
  add("output,o", po::value(&output_path)->required(), "output picture, .png");
  add("size", po::value(&size), "image size WIDTHxHEIGHT (default 800x600)");
  add("camera", po::value(&camera),
      "3D: ex,ey,ez,tx,ty,tz[,fov] (eye, target, degrees) or ortho,ex,ey,ez,tx,ty,tz,height "
      "(default: the bounds seen from (1,-0.8,0.6))");
  add("light", po::value(&light), "3D: direction towards the light dx,dy,dz (default 0.4,-0.6,0.8)");
  add("shadows", "3D: cast shadows");
  add("materials", "3D: colour each named primitive of a JSON model differently");
  add("hit", po::value(&hit),
      "3D: how rays find the surface: interval (bisection, default) or sphere (sphere tracing)");
  add("bounds", po::value(&bounds), "xmin,xmax,ymin,ymax[,zmin,zmax] (default: the model's \"bounds\")");
  add("rfunction", po::value(&rfunction), "default R-function (as for sage field)");
  add("quiet,q", "no summary");
  geometry::LoadOptions load;
  SourceOptionText source_text;
  add_source_options(options, load, source_text);
  po::variables_map vm;
  if (!parse_model_command(args, options, model_path, vm)) return 0;
  finish_source_options(vm, load, source_text);
  int width = 0, height = 0;
  parse_size(size, width, height);
  if (hit != "interval" && hit != "sphere") throw UsageError{"--hit: expected interval or sphere, not \"" + hit + "\""};
  check_output(output_path);

  const geometry::Model model =
      load_model(model_path, vm.count("rfunction") ? std::optional<std::string>(rfunction) : std::nullopt, load);
  const Grid box =
      grid_for(model, std::nullopt, vm.count("bounds") ? std::optional<std::string>(bounds) : std::nullopt);
  const bool quiet = vm.count("quiet") > 0;
  if (model.dimension == 2) {
    render::MapOptions o;
    o.width = width, o.height = height;
    output::write_png(output_path, render::render_map(model.field, box.lo, box.hi, o));
    if (!quiet) std::cout << "wrote " << output_path << ": " << width << "x" << height << " colour map\n";
    return 0;
  }
  render::SolidOptions o;
  o.width = width, o.height = height;
  o.camera = vm.count("camera") ? usage_checked([&] { return render::parse_camera(camera); })
                                : render::camera_for_box(box.lo, box.hi);
  if (vm.count("light")) o.light_direction = usage_checked([&] { return render::parse_vec3(light, "--light"); });
  o.shadows = vm.count("shadows") > 0;
  o.method = hit == "sphere" ? render::HitMethod::SphereTracing : render::HitMethod::IntervalBisection;
  if (vm.count("materials"))
    for (const auto& p : model.primitives)
      if (!p.name.empty() && model.named.count(p.name)) o.materials.push_back(model.named.at(p.name));
  const render::SolidPicture pic = render::render_solid(model.field, box.lo, box.hi, o);
  output::write_png(output_path, pic.image);
  if (!quiet)
    std::cout << "wrote " << output_path << ": " << width << "x" << height << ", " << pic.stats.rays << " rays ("
              << pic.stats.hits << " hits) in " << pic.stats.seconds << " s, "
              << static_cast<long long>(pic.stats.rays / std::max(pic.stats.seconds, 1e-9)) << " rays/s, "
              << pic.stats.interval_evaluations << " interval and " << pic.stats.point_evaluations
              << " point evaluations\n";
  return 0;
}

}  // namespace sage::cli
