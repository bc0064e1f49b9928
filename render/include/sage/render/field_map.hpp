#pragma once
// Pictures of 2D fields: render_map draws a field as a colour map (warm
// inside, cool outside) with isolines and the zero contour in bold; line
// widths come from |omega - level| / |grad omega|, the distance to the line
// in pixels, so lines stay even where the field is steep or flat. Uses all
// OpenMP threads.

#include <sage/expression/expression.hpp>
#include <sage/output/rgb_image.hpp>
#include <sage/render/camera.hpp>

namespace sage::render {

struct MapOptions {
  int width = 800;
  int height = 600;
  int isolines = 10;  // about this many levels across the field's range
};

/// The 2D field over [box_min, box_max] (x, y), scaled to fit the image
/// with square pixels. Throws std::invalid_argument for an empty image or box.
output::RgbImage render_map(const Expr& field, const Vec3& box_min, const Vec3& box_max, const MapOptions& options);

}  // namespace sage::render
