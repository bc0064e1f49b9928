#include <sage/expression/blend.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace sage {

BlendFunction blend_function_from_number(int number) {
  if (number < 1 || number > 6)
    throw std::invalid_argument("blend function must be 1 to 6 (paper 000), not " + std::to_string(number));
  return static_cast<BlendFunction>(number);
}

double blend_threshold(BlendFunction fb, double n) {
  switch (fb) {
    case BlendFunction::Sqrt:
    case BlendFunction::Rational: return n == 0 ? 0.0 : std::numeric_limits<double>::infinity();
    case BlendFunction::CosOver: return 5 * M_PI * n / 6;
    case BlendFunction::Cos: return M_PI * n / 6;
    case BlendFunction::Quadratic: return n / 4;
    case BlendFunction::Linear: return 2 * n;
  }
  return 0.0;
}

Expr blend_amount(const Expr& x, BlendFunction fb, double n) {
  if (!(n >= 0) || !std::isfinite(n)) throw std::invalid_argument("blend amount n must be finite and >= 0");
  if (n == 0) return Expr(0.0);  // plain CSG; 2 to 5 would divide by n
  switch (fb) {
    case BlendFunction::Sqrt: return (sqrt(square(x) + n) - x) * 0.5;
    case BlendFunction::Rational: return n / (x + std::sqrt(2 * n));
    // Clamping the argument at the threshold, where cos reaches -1 with
    // zero slope, gives exactly 0 beyond it.
    case BlendFunction::CosOver: return n * (cos(M_PI / 6 + min(x / n, Expr(5 * M_PI / 6))) + 1.0);
    case BlendFunction::Cos: return n * (cos(5 * M_PI / 6 + min(x / n, Expr(M_PI / 6))) + 1.0);
    case BlendFunction::Quadratic: return n * square(min(x / n - 0.25, Expr(0.0)));
    case BlendFunction::Linear: return max(n - x * 0.5, Expr(0.0));
  }
  return Expr(0.0);
}

Expr blend_union(const Expr& f1, const Expr& f2, BlendFunction fb, double n) {
  return max(f1, f2) + blend_amount(abs(f1 - f2), fb, n);
}

Expr blend_intersection(const Expr& f1, const Expr& f2, BlendFunction fb, double n) {
  return min(f1, f2) - blend_amount(abs(f1 - f2), fb, n);
}

Expr blend_difference(const Expr& f1, const Expr& f2, BlendFunction fb, double n) {
  return blend_intersection(f1, -f2, fb, n);
}

}  // namespace sage
