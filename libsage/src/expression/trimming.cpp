#include <sage/expression/derivative.hpp>
#include <sage/expression/normalize.hpp>
#include <sage/expression/trimming.hpp>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace sage {

TrimMethod parse_trim_method(const std::string& text) {
  if (text == "simple") return TrimMethod::Simple;
  if (text == "normalized") return TrimMethod::Normalized;
  if (text == "smooth") return TrimMethod::Smooth;
  throw std::invalid_argument("unknown trimming method '" + text + "' (expected simple, normalized or smooth)");
}

Expr trim_simple(const Expr& h, const Expr& t, const RSystem& system) {
  return sqrt(clamp_nonneg(-r_and(-square(h), t, system)));
}

Expr trim_normalized(const Expr& h, const Expr& t) { return sqrt(square(h) + square((abs(t) - t) * 0.5)); }

Expr trim_smooth(const Expr& h, const Expr& t, double scale) {
  if (!(scale > 0) || !std::isfinite(scale)) throw std::invalid_argument("trimming scale must be positive and finite");
  // h^4 / scale^2 as (h / sqrt(scale))^4: an even power of a function that
  // vanishes on the carrier, which the tape specializer recognizes.
  const Expr h4 = scale == 1.0 ? pow_int(h, 4) : pow_int(h * (1.0 / std::sqrt(scale)), 4);
  const Expr root = sqrt(square(t) + h4);
  return sqrt(square(h) + square(root * 0.5 - t * 0.5));  // (root - t) / 2 in one Axpby
}

Expr orthogonalize(const Expr& h, const Expr& t, int dimension) {
  const auto gh = gradient(h, dimension);
  const auto gt = gradient(t, dimension);
  Expr dot = 0.0;
  for (int i = 0; i < dimension; ++i) dot += gh[i] * gt[i];
  return normalize(t - h * dot, dimension);
}

Expr line_halfplane(const std::array<double, 2>& a, const std::array<double, 2>& b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], length = std::hypot(dx, dy);
  const double nx = -dy / length, ny = dx / length;
  return (Expr::x() * nx + Expr::y() * ny) - (a[0] * nx + a[1] * ny);
}

Expr segment_field(const std::array<double, 2>& a, const std::array<double, 2>& b, TrimMethod method,
                   const RSystem& system) {
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double length = std::hypot(dx, dy);
  if (!(length > 0)) throw std::invalid_argument("segment of zero length");
  const Expr x = Expr::x(), y = Expr::y();
  // As halfplanes and Axpbys: 18 instructions, none a division (was 20).
  const Expr h = line_halfplane(a, b);
  const double cx = 0.5 * (a[0] + b[0]), cy = 0.5 * (a[1] + b[1]);
  const Expr t = square(x - cx) * (-1.0 / length) + square(y - cy) * (-1.0 / length) + 0.25 * length;
  switch (method) {
    case TrimMethod::Simple: return trim_simple(h, t, system);
    case TrimMethod::Normalized: return trim_normalized(h, t);
    case TrimMethod::Smooth: return trim_smooth(h, t, length);
  }
  return trim_smooth(h, t, length);
}

Expr triangle_field(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c,
                    const RSystem& system, bool orthogonal) {
  using V = std::array<double, 3>;
  auto sub = [](const V& u, const V& v) { return V{u[0] - v[0], u[1] - v[1], u[2] - v[2]}; };
  auto cross = [](const V& u, const V& v) {
    return V{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  };
  auto unit = [](const V& v) {
    const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return V{v[0] / length, v[1] / length, v[2] / length};
  };
  auto dot = [](const V& u, const V& v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  auto linear = [&](const V& g, double constant) { return x * g[0] + y * g[1] + z * g[2] + constant; };
  const V n = unit(cross(sub(b, a), sub(c, a)));
  const Expr h = linear({-n[0], -n[1], -n[2]}, dot(n, a));
  const std::array<V, 3> vertices{a, b, c};
  std::vector<Expr> sides;
  for (std::size_t j = 0; j < 3; ++j) {
    const V& from = vertices[j];
    const V m = unit(cross(n, sub(vertices[(j + 1) % 3], from)));
    sides.push_back(linear(m, -dot(m, from)));
  }
  Expr t = r_conjunction_n(std::move(sides), system);
  if (orthogonal) t = orthogonalize(h, t, 3);
  return trim_smooth(h, t);
}

}  // namespace sage
