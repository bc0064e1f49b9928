#include <sage/bounded.hpp>
#include <sage/evaluator.hpp>
#include <sage/tape.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace sage {

Expr bounded_potential(const Expr& omega, double width) {
  if (!(width > 0) || !std::isfinite(width)) throw std::invalid_argument("support width must be positive");
  const Expr t = max(min(omega / width, Expr(1.0)), Expr(-1.0));
  return square(1.0 + t) * (2.0 - t) * 0.25;
}

namespace {

/// Level c of the arc through (X, Y) for the homothetic ellipses with
/// centre (c h, c v) and semi-axes c |1 - h|, c |1 - v|: the roots of
/// A c^2 - 2 B c + D = 0. far_arc: the exit point of the ray from the
/// origin (union), written D / (B + sqrt(B^2 - A D)) so that it has no
/// cancellation and holds for either sign of A; otherwise the entry point
/// (intersection, where A > 0).
Expr arc_level(const Expr& X, const Expr& Y, double h, double v, bool far_arc) {
  const double a2 = (1 - h) * (1 - h), b2 = (1 - v) * (1 - v);
  const double A = b2 * h * h + a2 * v * v - a2 * b2;
  const Expr B = b2 * h * X + a2 * v * Y;
  const Expr D = b2 * square(X) + a2 * square(Y);
  // Clamped: outside the transition zone the value is multiplied by 0.
  const Expr root = sqrt(clamp_nonneg(square(B) - A * D));
  return far_arc ? div_safe(D, B + root) : (B + root) / A;
}

/// The clamped cubic spline (zero end slopes) through (knots[i],
/// values[i]), minus 1, as an expression of u: 0 outside the knots, where
/// the profile is 1.
Expr spline_minus_one(const Expr& u, const std::vector<double>& knots, const std::vector<double>& values) {
  const std::size_t n = knots.size();
  std::vector<double> h(n - 1), diag(n), upper(n), rhs(n), M(n);
  for (std::size_t i = 0; i + 1 < n; ++i) h[i] = knots[i + 1] - knots[i];
  auto slope = [&](std::size_t i) { return (values[i + 1] - values[i]) / h[i]; };
  // Second derivatives M from the tridiagonal system (Thomas algorithm);
  // rows 0 and n-1 are the zero-slope end conditions.
  std::vector<double> lower(n, 0.0);
  diag[0] = 2 * h[0], upper[0] = h[0], rhs[0] = 6 * slope(0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    lower[i] = h[i - 1], diag[i] = 2 * (h[i - 1] + h[i]), upper[i] = h[i];
    rhs[i] = 6 * (slope(i) - slope(i - 1));
  }
  lower[n - 1] = h[n - 2], diag[n - 1] = 2 * h[n - 2], upper[n - 1] = 0, rhs[n - 1] = -6 * slope(n - 2);
  for (std::size_t i = 1; i < n; ++i) {
    const double w = lower[i] / diag[i - 1];
    diag[i] -= w * upper[i - 1];
    rhs[i] -= w * rhs[i - 1];
  }
  M[n - 1] = rhs[n - 1] / diag[n - 1];
  for (std::size_t i = n - 1; i-- > 0;) M[i] = (rhs[i] - upper[i] * M[i + 1]) / diag[i];

  Expr sum(0.0);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const Expr left = u - knots[k], right = knots[k + 1] - u;
    const Expr piece = M[k] / (6 * h[k]) * pow_int(right, 3) + M[k + 1] / (6 * h[k]) * pow_int(left, 3) +
                       (values[k] / h[k] - M[k] * h[k] / 6) * right +
                       (values[k + 1] / h[k] - M[k + 1] * h[k] / 6) * left;
    // step(0) = 1/2: at a knot the two pieces (equal to second order) are averaged.
    sum += (step(left) - step(-right)) * (piece - 1.0);
  }
  return sum;
}

}  // namespace

Expr bounded_compose(BoundedOp op, const Expr& f1, const Expr& f2, const BoundedTransition& tr, int dimension) {
  if (!(tr.theta1 > 0 && tr.theta1 < M_PI / 4))
    throw std::invalid_argument("theta1 must lie strictly between 0 and 45 degrees");
  if (!(tr.theta2 > M_PI / 4 && tr.theta2 < M_PI / 2))
    throw std::invalid_argument("theta2 must lie strictly between 45 and 90 degrees");
  if (!(tr.iso > 0 && tr.iso < 1)) throw std::invalid_argument("iso-value C must lie strictly between 0 and 1");
  const Expr X = f1;
  const Expr Y = op == BoundedOp::Difference ? 2 * tr.iso - f2 : f2;
  const double tan1 = std::tan(tr.theta1), cot2 = 1 / std::tan(tr.theta2);
  const bool is_union = op == BoundedOp::Union;

  // Zones by angle; step(0) = 1/2 on a border, where both sides agree to first order.
  const Expr below = step(tan1 * X - Y);  // theta <= theta1
  const Expr above = step(cot2 * Y - X);  // theta >= theta2
  const Expr between = 1.0 - below - above;
  const Expr arc = is_union ? arc_level(X, Y, cot2, tan1, true) : arc_level(X, Y, 1 / tan1, 1 / cot2, false);
  const Expr straight = is_union ? below * X + above * Y : below * Y + above * X;
  if (tr.profile_points.empty()) return straight + between * arc;

  // Profile knots in u = Y / (X + Y), from the control points.
  const Tape tape(std::vector<Expr>{X, Y, straight + between * arc}, dimension);
  Evaluator<double> eval(tape);
  std::vector<double> knots{tan1 / (1 + tan1)}, values{1.0};
  for (std::size_t i = 0; i < tr.profile_points.size(); ++i) {
    eval.evaluate(tr.profile_points[i].data());
    const double x = eval.result(0), y = eval.result(1), g = eval.result(2);
    const double u = x + y > 0 ? y / (x + y) : -1;
    const std::string which = "profile point " + std::to_string(i + 1);
    const bool in_transition = y > tan1 * x && x > cot2 * y && g > 0;
    if (!in_transition) throw std::invalid_argument(which + " is not inside the transition zone of both potentials");
    if (!(u > knots.back())) throw std::invalid_argument(which + " must lie at a larger angle than the one before");
    knots.push_back(u);
    values.push_back(tr.iso / g);
  }
  const double u2 = 1 / (1 + cot2);
  if (!(u2 > knots.back())) throw std::invalid_argument("the last profile point lies beyond theta2");
  knots.push_back(u2);
  values.push_back(1.0);
  const Expr u = div_safe(Y, X + Y);
  return straight + between * arc * (1.0 + spline_minus_one(u, knots, values));
}

}  // namespace sage
