#include <sage/render/field_map.hpp>

#include <sage/scalars/tuple.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sage::render {

namespace {

/// Diverging colour map: blue (outside, s = -1) through near-white (the
/// boundary, s = 0) to red (inside, s = 1).
Vec3 diverging(double s) {
  s = std::clamp(s, -1.0, 1.0);
  const Vec3 white{0.97, 0.96, 0.94}, red{0.75, 0.18, 0.15}, blue{0.2, 0.35, 0.72};
  const Vec3& end = s > 0 ? red : blue;
  const double w = std::abs(s);
  return (1 - w) * white + w * end;
}

/// 1, 2 or 5 times a power of ten, near `x`.
double nice_step(double x) {
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  const double m = x / p;
  return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}

/// Coverage of a line `half_width` pixels wide at distance d pixels, with
/// one pixel of anti-aliasing.
double line_coverage(double d, double half_width) { return std::clamp(half_width + 0.5 - d, 0.0, 1.0); }

}  // namespace

output::RgbImage render_map(const Expr& field, const Vec3& box_min, const Vec3& box_max, const MapOptions& o) {
  if (o.width <= 0 || o.height <= 0) throw std::invalid_argument("image size must be positive");
  if (!(box_max[0] > box_min[0] && box_max[1] > box_min[1])) throw std::invalid_argument("the map box is empty");
  // Square pixels: the box fits the image, centred.
  const double pixel = std::max((box_max[0] - box_min[0]) / o.width, (box_max[1] - box_min[1]) / o.height);
  const double cx = 0.5 * (box_min[0] + box_max[0]), cy = 0.5 * (box_min[1] + box_max[1]);
  const Tape tape(field, 2);
  const std::size_t count = static_cast<std::size_t>(o.width) * o.height;
  std::vector<double> value(count), slope(count);

#pragma omp parallel
  {
    Evaluator<Tuple<2, 1>> eval(tape);
#pragma omp for schedule(static)
    for (int py = 0; py < o.height; ++py)
      for (int px = 0; px < o.width; ++px) {
        const double x = cx + (px + 0.5 - 0.5 * o.width) * pixel, y = cy - (py + 0.5 - 0.5 * o.height) * pixel;
        const auto t = eval.at({x, y, 0});
        const auto g = t.gradient();
        const std::size_t i = static_cast<std::size_t>(py) * o.width + px;
        value[i] = t.value();
        slope[i] = std::hypot(g[0], g[1]) * pixel;  // change of omega per pixel
      }
  }
  // Inside and outside scaled apart: the outside usually spans far more.
  double inside = 0, outside = 0;
  for (double v : value)
    if (std::isfinite(v)) (v > 0 ? inside : outside) = std::max(v > 0 ? inside : outside, std::abs(v));
  const double extent = std::max(inside, outside);
  const double step = extent > 0 ? nice_step(extent / std::max(1, o.isolines)) : 1.0;

  output::RgbImage image(o.width, o.height);
  for (std::size_t i = 0; i < count; ++i) {
    const double v = value[i];
    Vec3 c{0.5, 0.5, 0.5};  // NaN: grey
    if (std::isfinite(v)) {
      c = diverging(v > 0 ? v / inside : v < 0 ? v / outside : 0.0);
      if (slope[i] > 0) {
        const double level = std::round(v / step) * step;
        const double iso = line_coverage(std::abs(v - level) / slope[i], 0.35);
        const double zero = line_coverage(std::abs(v) / slope[i], 1.2);
        c = (1 - 0.45 * iso) * c;
        c = (1 - zero) * c;
      }
    }
    for (int k = 0; k < 3; ++k)
      image.rgb[3 * i + k] = static_cast<std::uint8_t>(std::clamp(c[k], 0.0, 1.0) * 255 + 0.5);
  }
  return image;
}

}  // namespace sage::render
