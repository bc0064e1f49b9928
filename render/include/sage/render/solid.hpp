#pragma once
// Pictures of 3D fields: render_solid ray casts a field (omega >= 0 inside)
// inside a box and shades the first hits: exact normals from first-order
// tuples (the outward normal is -grad omega / |grad omega|), ambient +
// diffuse + specular (Blinn-Phong) light from one direction, optional
// shadows (a second ray towards the light). Uses all OpenMP threads.

#include <sage/expression/expression.hpp>
#include <sage/output/rgb_image.hpp>
#include <sage/render/camera.hpp>
#include <sage/render/ray_cast.hpp>

#include <vector>

namespace sage::render {

struct SolidOptions {
  int width = 800;
  int height = 600;
  Camera camera;
  Vec3 light_direction{0.4, -0.6, 0.8};  // towards the light
  bool shadows = false;
  HitMethod method = HitMethod::IntervalBisection;
  /// Interval bisection specializes the tape to ray segments (min/max
  /// trees); false for the baseline of benchmarks.
  bool prune_tapes = true;
  /// Leaf width of interval bisection, relative to the box diagonal.
  double relative_leaf_width = 1e-6;
  /// Primitive fields (omega_i): a hit takes the colour of the primitive
  /// whose |omega_i| is smallest there. Empty: one colour.
  std::vector<Expr> materials;
};

struct RenderStats {
  long long rays = 0;  // primary and shadow rays
  long long hits = 0;  // primary rays that hit
  long long interval_evaluations = 0;
  long long point_evaluations = 0;
  double seconds = 0;
};

struct SolidPicture {
  output::RgbImage image;
  std::vector<double> depth;  // per pixel, top row first; infinity where the ray missed
  RenderStats stats;
};

/// Throws std::invalid_argument for an empty image or box.
SolidPicture render_solid(const Expr& field, const Vec3& box_min, const Vec3& box_max, const SolidOptions& options);

}  // namespace sage::render
