#include <sage/expression/bounded.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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
/// Second derivatives of the clamped cubic spline (zero end slopes)
/// through (knots[i], values[i]).
std::vector<double> spline_moments(const std::vector<double>& knots, const std::vector<double>& values) {
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
  return M;
}

/// The profile m(u): the spline through (knots[i], values[i]) on
/// [knots.front(), knots.back()], 1 outside, written in the truncated power
/// basis, 1 + M0 l^2 / 2 + c l^3 + sum_k d_k max(l - l_k, 0)^3 with l = u
/// clamped to the knots minus the first knot. It has no steps, so its
/// intervals shrink with the box everywhere, knots included (selecting
/// pieces by steps gave [0, 1] weights at every knot at any width). The
/// end values are 1 with zero slope, so clamping keeps it C1.
Expr profile_factor(const Expr& u, const std::vector<double>& knots, const std::vector<double>& M) {
  const std::size_t n = knots.size();
  std::vector<double> h(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) h[i] = knots[i + 1] - knots[i];
  const Expr l = min(max(u, Expr(knots[0])), Expr(knots[n - 1])) - knots[0];
  // The first piece: value 1, slope 0, second derivative M0, third (M1 - M0) / h0.
  Expr m = 1.0 + (M[0] / 2) * square(l) + ((M[1] - M[0]) / (6 * h[0])) * pow_int(l, 3);
  for (std::size_t k = 1; k + 1 < n; ++k) {
    // The jump of the third derivative at knot k, over 3!.
    const double d = ((M[k + 1] - M[k]) / h[k] - (M[k] - M[k - 1]) / h[k - 1]) / 6;
    m += d * pow_int(max(l - (knots[k] - knots[0]), Expr(0.0)), 3);
  }
  return m;
}

/// Linear bounds of the unprofiled operator, for tight intervals. G is
/// homogeneous of degree 1 and its level-1 curve is convex, so lines
/// tangent to the quarter ellipse bound it on one side (exact at the
/// tangent points) and its chords on the other: for union, max(X, Y,
/// tangents) <= G <= max(X, Y, chords); for intersection, min(X, Y, chords)
/// <= G <= min(X, Y, tangents). These are monotone in X and Y, so their
/// natural interval extensions are exact, whereas the zone steps of G give
/// [0, 1] wherever X or Y straddles a border (outside the supports X = Y =
/// 0 up to outward rounding, where G's interval is the whole line). The
/// coefficients are moved outward by 1e-12 relative to cover their rounding.
std::pair<Expr, Expr> linear_bounds(const Expr& X, const Expr& Y, double tan1, double cot2, bool is_union) {
  constexpr int kPieces = 16;
  // Level-1 arc: union centre (cot2, tan1), semi-axes (1 - cot2, 1 - tan1),
  // from (1, tan1) to (cot2, 1); intersection centre (1 / tan1, 1 / cot2),
  // semi-axes (1 / tan1 - 1, 1 / cot2 - 1), from (1 / tan1, 1) to (1, 1 / cot2).
  auto arc = [&](double phi) -> std::array<double, 2> {
    if (is_union) return {cot2 + (1 - cot2) * std::cos(phi), tan1 + (1 - tan1) * std::sin(phi)};
    return {1 / tan1 - (1 / tan1 - 1) * std::sin(phi), 1 / cot2 - (1 / cot2 - 1) * std::cos(phi)};
  };
  auto form = [&](double nx, double ny, const std::array<double, 2>& through, double scale) {
    const double n = nx * through[0] + ny * through[1];
    return (scale * nx / n) * X + (scale * ny / n) * Y;
  };
  const double inner = 1 - 1e-12, outer = 1 + 1e-12;
  // Union: tangents below G (scaled in), chords above (scaled out);
  // intersection: chords below, tangents above.
  const double tangent_scale = is_union ? inner : outer, chord_scale = is_union ? outer : inner;
  auto pick = [&](const Expr& a, const Expr& b) { return is_union ? max(a, b) : min(a, b); };
  Expr tangents = pick(X, Y), chords = pick(X, Y);
  const double a = is_union ? 1 - cot2 : 1 / tan1 - 1, b = is_union ? 1 - tan1 : 1 / cot2 - 1;
  for (int k = 0; k <= kPieces; ++k) {
    const double phi = k * M_PI / (2 * kPieces);
    const auto p = arc(phi);
    // Normal of the ellipse at p (positive components).
    const double nx = is_union ? b * std::cos(phi) : b * std::sin(phi),
                 ny = is_union ? a * std::sin(phi) : a * std::cos(phi);
    if (k > 0 && k < kPieces) tangents = pick(tangents, form(nx, ny, p, tangent_scale));
    if (k < kPieces) {
      const auto q = arc((k + 1) * M_PI / (2 * kPieces));
      chords = pick(chords, form(q[1] - p[1], p[0] - q[0], p, chord_scale));
    }
  }
  return is_union ? std::make_pair(tangents, chords) : std::make_pair(chords, tangents);
}

/// The smooth union's arc-of-ellipse field (zones by angle, no clamp).
Expr smooth_union(const Expr& X, const Expr& Y, double tan1, double cot2) {
  const Expr below = step(tan1 * X - Y), above = step(cot2 * Y - X);
  return below * X + above * Y + (1.0 - below - above) * arc_level(X, Y, cot2, tan1, true);
}

/// The sharp union and its upper bound (bounded.hpp). Corner coordinates
/// P = (c - X) / a, Q = (c - Y) / b with a = 1 - cot theta2, b = 1 - tan
/// theta1; the arc of level c is N(P, Q) = P + Q + sqrt(2 P Q) = rho.
struct SharpUnion {
  Expr value;  // clamped between max(X, Y) and `upper`
  Expr upper;
};

SharpUnion sharp_union(const Expr& X, const Expr& Y, double tan1, double cot2, double C) {
  const double a = 1 - cot2, b = 1 - tan1;
  // Chord gauge: s = 1 at (1, tan theta1) and (cot theta2, 1).
  const double alpha = b / (a + b - a * b), beta = a / (a + b - a * b);
  const Expr s = alpha * X + beta * Y;
  const Expr M = max(X, Y);
  // Levels c <= C: rho = (1 - c / C) s. With g(c) = rho - P - Q = g0 - g1 c,
  // squaring g = sqrt(2 P Q) gives A c^2 - 2 B c + D = 0, A = g1^2 - k > 0
  // (k = 2 / (a b)); the arc is the root where the quadratic decreases, the
  // smaller one, D / (B + sqrt(B^2 - A D)) (B > 0 on the arc, so no
  // cancellation). B^2 - A D = k g(X) g(Y) + (k / 2)^2 (X - Y)^2, a sum of
  // two terms >= 0 on the arc: written so, its interval does not straddle 0
  // by cancellation (as B^2 - A D did, for narrow zones).
  const double k = 2 / (a * b);
  const Expr g0 = s + X / a + Y / b, g1 = s / C + (1 / a + 1 / b);
  const Expr B = g0 * g1 - (k / 2) * (X + Y);
  const Expr D = square(g0) - k * X * Y;
  // g at c = X and c = Y: one of P, Q is 0 there.
  const Expr gx = (1.0 - X / C) * s - (X - Y) / b, gy = (1.0 - Y / C) * s - (Y - X) / a;
  const Expr discriminant = k * gx * gy + (k * k / 4) * square(X - Y);
  const Expr low_arc = div_safe(D, B + sqrt(clamp_nonneg(discriminant)));
  // Straight where the arc of level X (or Y) has not begun yet: Y below the
  // tangent point, g(X) <= 0, i.e. X - Y >= b (1 - X / C) s (resp. g(Y) <= 0).
  const Expr vertical = step(-gx);
  const Expr horizontal = step(-gy);
  const Expr low = vertical * X + horizontal * Y + (1.0 - vertical - horizontal) * low_arc;
  // Levels c >= C: rho = c - C, the smooth union homothetic about (C, C).
  const Expr high = C + smooth_union(X - C, Y - C, tan1, cot2);
  const Expr above_corner = step(M - C);
  const Expr g = above_corner * high + (1.0 - above_corner) * low;

  // Upper bound: 0 <= dG/dX, dG/dY <= 1 and G = X up to the tangent point
  // (X, Yt(X)), so G <= X + max(Y - Yt(X), 0); likewise in Y. Exact on the
  // straight parts, where the zone steps switch.
  const Expr Xc = min(X, Expr(C)), Yc = min(Y, Expr(C));
  const Expr tx = 1.0 - Xc / C, ty = 1.0 - Yc / C;
  const Expr Yt = Xc * (1.0 - (b * alpha) * tx) / (1.0 + (b * beta) * tx) + tan1 * max(X - C, Expr(0.0));
  const Expr Xt = Yc * (1.0 - (a * beta) * ty) / (1.0 + (a * alpha) * ty) + cot2 * max(Y - C, Expr(0.0));
  const Expr bound = min(X + max(Y - Yt, Expr(0.0)), Y + max(X - Xt, Expr(0.0)));
  // Where an input is <= 0, G = max(X, Y) and the bound above may not hold.
  const Expr upper = max(M, bound * (1 + 1e-12));
  return {min(max(g, M), upper), upper};
}

/// The sharp intersection X Y / U(X, Y) with U the sharp union (as min =
/// X Y / max), on the positive parts; min(X, Y, 0) carries negative inputs.
Expr sharp_intersection(const Expr& X, const Expr& Y, double tan1, double cot2, double C) {
  const Expr Xp = max(X, Expr(0.0)), Yp = max(Y, Expr(0.0));
  const SharpUnion u = sharp_union(Xp, Yp, tan1, cot2, C);
  const Expr product = Xp * Yp;
  // U <= upper gives the lower bound; U >= max gives min(X, Y) above.
  const Expr lower = max(Expr(0.0), div_safe(product, u.upper) * (1 - 1e-12));
  const Expr j = min(max(div_safe(product, u.value), lower), min(Xp, Yp));
  return min(min(X, Y), Expr(0.0)) + j;
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
  if (tr.sharp) {
    if (!tr.profile_points.empty())
      throw std::invalid_argument(
          "profile points cannot shape the sharp transition: its level-C curve is the corner of f1 = C and f2 = C");
    return is_union ? sharp_union(X, Y, tan1, cot2, tr.iso).value : sharp_intersection(X, Y, tan1, cot2, tr.iso);
  }

  // Zones by angle; step(0) = 1/2 on a border, where both sides agree to first order.
  const Expr below = step(tan1 * X - Y);  // theta <= theta1
  const Expr above = step(cot2 * Y - X);  // theta >= theta2
  const Expr between = 1.0 - below - above;
  const Expr arc = is_union ? arc_level(X, Y, cot2, tan1, true) : arc_level(X, Y, 1 / tan1, 1 / cot2, false);
  const Expr straight = is_union ? below * X + above * Y : below * Y + above * X;
  const auto [lower, upper] = linear_bounds(X, Y, tan1, cot2, is_union);
  // Pointwise G itself (the bounds hold, and touch it only where they are
  // tangent to it); over intervals, no wider than the bounds.
  auto tightened = [&](const Expr& g, const Expr& lo, const Expr& hi) { return min(max(g, lo), hi); };
  if (tr.profile_points.empty()) return tightened(straight + between * arc, lower, upper);

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
  // G = G0 m(u): m = 1 outside the transition zone, where G0 is X or Y.
  return tightened(straight + between * arc, lower, upper) * profile_factor(u, knots, spline_moments(knots, values));
}

}  // namespace sage
