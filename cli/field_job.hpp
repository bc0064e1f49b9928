#pragma once
// One field job: read a model, sample its field on a grid, write a VTK
// file or (2D) a GeoTIFF. Shared by `sage field` and `sage demo`.

#include <sage/geometry/model.hpp>
#include <sage/sampling/field_samples.hpp>
#include <sage/sampling/grid.hpp>
#include <sage/sampling/sampling_plan.hpp>

#include <boost/program_options.hpp>

#include <optional>
#include <string>

namespace sage::cli {

struct FieldJob {
  std::string model_path;
  std::string output_path;
  std::optional<std::string> grid;       // "200x200" / "64x64x64"
  std::optional<double> resolution;      // in place of grid: points this far apart (the model's units)
  std::optional<std::string> bounds;     // "xmin,xmax,ymin,ymax[,zmin,zmax]"
  std::optional<std::string> rfunction;  // overrides the model's default
  geometry::LoadOptions load;            // GIS and mesh options
  int order = 1;
  // Far-field approximation: allowed deviation relative to the grid box's
  // diagonal (0 = exact sampling); unset: sage's default (plan_sampling).
  std::optional<double> tolerance;
  bool show_progress = true;
  bool float64 = false;                    // GeoTIFF bands in Float64 rather than Float32
  std::optional<std::string> crs_out;      // GeoTIFF: warp into this CRS (EPSG:XXXX, ...)
  std::optional<std::string> compression;  // GeoTIFF: "zstd", "deflate" or "none"
};

struct FieldReport {
  Grid grid;
  std::size_t instructions = 0;
  double omega_min = 0, omega_max = 0;
  double seconds_sampling = 0, seconds_writing = 0;
  SamplingPlan plan;  // how the grid was sampled (plan_sampling)
  // Far mesh faces in single precision: used, or tried and rejected (then
  // exact), and the largest deviation measured (relative to the diagonal).
  bool far_faces = false;
  bool far_faces_rejected = false;
  double far_faces_deviation = 0;
  // GeoTIFF output: its bands and coordinate reference system, in words.
  std::string geotiff;
};

/// Reads any geometry source with the job's options (throws ModelError).
geometry::Model load_model(const std::string& path, const std::optional<std::string>& rfunction,
                           geometry::LoadOptions options = {});

/// Adds the options for GIS data and meshes (--method, --feature, --where,
/// --layer, --crs, --repair, --orthogonalize) to a command's options,
/// writing into `options`; call finish_source_options after parsing.
struct SourceOptionText {
  std::string where, layer, crs;  // parsed as text, moved into LoadOptions when given
  int solid = 0;
  double deflection = 0;
};
void add_source_options(boost::program_options::options_description& description, geometry::LoadOptions& options,
                        SourceOptionText& text);
/// Parses a command line of the form MODEL [options] (with `points_path`:
/// MODEL POINTS [options]): stores the paths, prints `options` and returns
/// false for --help, else notifies.
/// --tolerance T or --exact (as --tolerance 0), checked: a usage error for
/// both or for T outside [0, 1e-2); unset when neither is given (sage's default).
std::optional<double> chosen_tolerance(const boost::program_options::variables_map& vm, double tolerance);

bool parse_model_command(const std::vector<std::string>& args,
                         const boost::program_options::options_description& options, std::string& model_path,
                         boost::program_options::variables_map& vm, std::string* points_path = nullptr);

void finish_source_options(const boost::program_options::variables_map& vm, geometry::LoadOptions& options,
                           const SourceOptionText& text);

/// The grid for a model: --grid / --bounds when given, else the model's
/// bounds and a default resolution (200x200 or 64x64x64). With `spacing`
/// (--resolution) in place of --grid, the points are that far apart from
/// the bounds' minimum on, up to the first point at or past their maximum.
Grid grid_for(const geometry::Model& model, const std::optional<std::string>& resolution,
              const std::optional<std::string>& bounds, std::optional<double> spacing = std::nullopt);

FieldReport run_field_job(const FieldJob& job);

}  // namespace sage::cli
