#include <sage/derivative.hpp>
#include <sage/solver/domain_quadrature.hpp>
#include <sage/solver/gauss.hpp>

#include <algorithm>
#include <cmath>

namespace sage::solver {

namespace {

std::vector<Expr> value_and_gradient(const Expr& omega, int dimension) {
  std::vector<Expr> roots{omega};
  for (const Expr& g : gradient(omega, dimension)) roots.push_back(g);
  return roots;
}

/// The root of f in [a, b] given f(a) and f(b) of opposite signs (Illinois
/// variant of regula falsi: superlinear, never leaves the bracket).
template <class F>
double bracketed_root(F&& f, double a, double b, double fa, double fb) {
  const double tolerance = 4e-16 * std::max(std::abs(a), std::abs(b)) + 1e-300;
  int side = 0;
  double c = a;
  for (int iteration = 0; iteration < 100 && std::abs(b - a) > tolerance; ++iteration) {
    c = (a * fb - b * fa) / (fb - fa);
    if (!(c > std::min(a, b) && c < std::max(a, b))) c = 0.5 * (a + b);
    const double fc = f(c);
    if (fc == 0.0) return c;
    if ((fc > 0) == (fb > 0)) {
      b = c;
      fb = fc;
      if (side == -1) fa *= 0.5;
      side = -1;
    } else {
      a = c;
      fa = fc;
      if (side == 1) fb *= 0.5;
      side = 1;
    }
  }
  return c;
}

/// Appends the roots of f in (a, b) found between `samples` equal steps.
template <class F>
void append_roots(F&& f, double a, double b, std::vector<double>& roots, int samples = 4) {
  double x0 = a, f0 = f(a);
  for (int s = 1; s <= samples; ++s) {
    const double x1 = a + (b - a) * s / samples, f1 = f(x1);
    if (f0 == 0.0 && s > 1) roots.push_back(x0);
    if ((f0 < 0 && f1 > 0) || (f0 > 0 && f1 < 0)) roots.push_back(bracketed_root(f, x0, x1, f0, f1));
    x0 = x1;
    f0 = f1;
  }
}

/// Calls visit(t, w) for a Gauss rule on each piece of [a, b] between the
/// sorted break points.
template <class Visit>
void gauss_on_pieces(double a, double b, std::vector<double> breaks, int points, Visit&& visit) {
  std::sort(breaks.begin(), breaks.end());
  const GaussRule& rule = gauss_legendre(points);
  double start = a;
  breaks.push_back(b);
  for (double end : breaks) {
    end = std::min(std::max(end, start), b);
    const double length = end - start;
    if (length > 1e-14 * (b - a)) {
      for (std::size_t k = 0; k < rule.nodes.size(); ++k)
        visit(start + length * rule.nodes[k], length * rule.weights[k]);
    }
    start = end;
  }
}

/// Sign margin of an interval: its distance from 0, or 0 if it holds 0.
double margin(const Interval& i) { return i.lo > 0 ? i.lo : (i.hi < 0 ? -i.hi : 0.0); }

}  // namespace

DomainTapes::DomainTapes(const Expr& omega, int dimension)
    : value(omega, dimension), enclosure(value_and_gradient(omega, dimension), dimension) {}

template <int D>
CellQuadrature<D>::CellQuadrature(const DomainTapes& tapes, QuadratureOptions options)
    : options_(options), value_(tapes.value), enclosure_(tapes.enclosure), gradient_(tapes.value) {}

template <int D>
double CellQuadrature<D>::omega_at(const std::array<double, D>& p) {
  value_.evaluate(p.data());
  return value_.result();
}

template <int D>
std::array<Interval, D + 1> CellQuadrature<D>::enclose(const Box<D>& box) {
  std::array<Interval, D> vars{};
  for (int a = 0; a < D; ++a) vars[a] = Interval(box.lo[a], box.hi[a]);
  enclosure_.evaluate_with(vars.data());
  std::array<Interval, D + 1> out{};
  for (int r = 0; r <= D; ++r) out[r] = enclosure_.result(static_cast<std::size_t>(r));
  return out;
}

template <int D>
CellKind CellQuadrature<D>::classify(const Box<D>& box) {
  const Interval w = enclose(box)[0];
  if (w.is_nan()) return CellKind::Cut;  // no proof either way: integrate with care
  if (w.lo > 0) return CellKind::Inside;
  if (w.hi < 0) return CellKind::Outside;
  return CellKind::Cut;
}

template <int D>
void CellQuadrature<D>::append_rule(const Box<D>& box, CellKind kind, std::vector<VolumePoint<D>>& volume,
                                    std::vector<SurfacePoint<D>>* surface) {
  const Target target{&volume, surface};
  if (kind == CellKind::Inside)
    tensor_rule(box, false, options_.inside_points > 0 ? options_.inside_points : options_.points, target);
  if (kind == CellKind::Cut) cut_rule(box, 0, target);
}

template <int D>
void CellQuadrature<D>::tensor_rule(const Box<D>& box, bool masked, int points, Target target) {
  const GaussRule& rule = gauss_legendre(points);
  const int q = points;
  int total = 1;
  for (int a = 0; a < D; ++a) total *= q;
  for (int k = 0; k < total; ++k) {
    VolumePoint<D> p{};
    p.weight = 1.0;
    int rest = k;
    for (int a = 0; a < D; ++a) {
      const auto n = static_cast<std::size_t>(rest % q);
      rest /= q;
      const double width = box.hi[a] - box.lo[a];
      p.x[a] = box.lo[a] + width * rule.nodes[n];
      p.weight *= width * rule.weights[n];
    }
    if (masked && omega_at(p.x) < 0) continue;
    target.volume->push_back(p);
  }
}

template <int D>
void CellQuadrature<D>::cut_rule(const Box<D>& box, int depth, Target target) {
  const auto enclosure = enclose(box);
  if (enclosure[0].lo > 0) return tensor_rule(box, false, options_.points, target);
  if (enclosure[0].hi < 0) return;
  int height = -1;
  double best = 0.0;
  for (int a = 0; a < D; ++a) {
    const double m = margin(enclosure[static_cast<std::size_t>(a + 1)]);
    if (m > best) {
      best = m;
      height = a;
    }
  }
  if (height < 0 && depth > 0) height = sampled_height(box, -1);
  if (height >= 0) return height_rule(box, height, target);
  if (depth >= options_.max_depth) return tensor_rule(box, true, options_.points, target);
  for (int child = 0; child < (1 << D); ++child) {
    Box<D> part = box;
    for (int a = 0; a < D; ++a) {
      const double mid = 0.5 * (box.lo[a] + box.hi[a]);
      if (child & (1 << a)) {
        part.lo[a] = mid;
      } else {
        part.hi[a] = mid;
      }
    }
    cut_rule(part, depth + 1, target);
  }
}

template <int D>
void CellQuadrature<D>::height_rule(const Box<D>& box, int e, Target target) {
  if constexpr (D == 2) {
    const int b = 1 - e;
    std::vector<double> breaks;
    for (const double face : {box.lo[e], box.hi[e]}) {
      auto on_face = [&](double t) {
        std::array<double, D> p{};
        p[b] = t;
        p[e] = face;
        return omega_at(p);
      };
      append_roots(on_face, box.lo[b], box.hi[b], breaks);
    }
    gauss_on_pieces(box.lo[b], box.hi[b], breaks, options_.points, [&](double t, double w) {
      std::array<double, D> p{};
      p[b] = t;
      line_rule(p, e, box, w, target);
    });
  } else {
    base_rule_2d(box, e, box, 0, target);
  }
}

template <int D>
void CellQuadrature<D>::base_rule_2d(const Box<D>& box, int e, const Box<D>& base, int depth, Target target) {
  // The base is `base` with axis e ignored; the level sets on it are omega
  // on the bottom and top faces of `box`.
  int axes[2], n = 0;
  for (int a = 0; a < D; ++a)
    if (a != e) axes[n++] = a;
  std::vector<double> faces;
  std::vector<std::array<Interval, D + 1>> face_enclosures;
  for (const double face : {box.lo[e], box.hi[e]}) {
    Box<D> face_box = base;
    face_box.lo[e] = face_box.hi[e] = face;
    const auto enclosure = enclose(face_box);
    if (enclosure[0].contains_zero() || enclosure[0].is_nan()) {
      faces.push_back(face);
      face_enclosures.push_back(enclosure);
    }
  }
  auto base_point = [&](double u, double v, double w) {
    std::array<double, D> p{};
    p[axes[0]] = u;
    p[axes[1]] = v;
    line_rule(p, e, box, w, target);
  };
  const GaussRule& rule = gauss_legendre(options_.points);
  auto plain = [&] {
    const double wu = base.hi[axes[0]] - base.lo[axes[0]], wv = base.hi[axes[1]] - base.lo[axes[1]];
    for (std::size_t i = 0; i < rule.nodes.size(); ++i)
      for (std::size_t j = 0; j < rule.nodes.size(); ++j)
        base_point(base.lo[axes[0]] + wu * rule.nodes[i], base.lo[axes[1]] + wv * rule.nodes[j],
                   wu * wv * rule.weights[i] * rule.weights[j]);
  };
  if (faces.empty()) return plain();
  // A base height direction along which every face level set is monotone.
  int height = -1;
  double best = 0.0;
  for (int k = 0; k < 2; ++k) {
    double m = 1e300;
    for (const auto& enclosure : face_enclosures)
      m = std::min(m, margin(enclosure[static_cast<std::size_t>(axes[k] + 1)]));
    if (m > best) {
      best = m;
      height = axes[k];
    }
  }
  if (height < 0 && depth > 0) height = sampled_height(base, e, faces);
  if (height < 0) {
    if (depth >= options_.max_depth) return plain();
    for (int child = 0; child < 4; ++child) {
      Box<D> part = base;
      for (int k = 0; k < 2; ++k) {
        const int a = axes[k];
        const double mid = 0.5 * (base.lo[a] + base.hi[a]);
        if (child & (1 << k)) {
          part.lo[a] = mid;
        } else {
          part.hi[a] = mid;
        }
      }
      base_rule_2d(box, e, part, depth + 1, target);
    }
    return;
  }
  const int t_axis = axes[0] == height ? axes[1] : axes[0];
  auto omega_face = [&](double face, double t, double s) {
    std::array<double, D> p{};
    p[e] = face;
    p[t_axis] = t;
    p[height] = s;
    return omega_at(p);
  };
  std::vector<double> breaks;
  for (const double face : faces)
    for (const double s : {base.lo[height], base.hi[height]})
      append_roots([&](double t) { return omega_face(face, t, s); }, base.lo[t_axis], base.hi[t_axis], breaks);
  gauss_on_pieces(base.lo[t_axis], base.hi[t_axis], breaks, options_.points, [&](double t, double wt) {
    std::vector<double> line_breaks;
    for (const double face : faces)
      append_roots([&](double s) { return omega_face(face, t, s); }, base.lo[height], base.hi[height], line_breaks, 2);
    gauss_on_pieces(base.lo[height], base.hi[height], line_breaks, options_.points, [&](double s, double ws) {
      if (t_axis == axes[0]) {
        base_point(t, s, wt * ws);
      } else {
        base_point(s, t, wt * ws);
      }
    });
  });
}

template <int D>
int CellQuadrature<D>::sampled_height(const Box<D>& box, int fixed_axis, const std::vector<double>& faces) {
  // Interval bounds of derivatives of deep expressions (normalized fields)
  // are often too loose to prove monotonicity. Accept a direction in which
  // the derivative keeps one sign at the corners and the centre; the line
  // rule below copes with the rare line that meets the boundary twice.
  std::vector<std::array<double, D>> samples;
  const std::vector<double> levels = faces.empty() ? std::vector<double>{0.0} : faces;
  for (const double level : levels) {
    for (int corner = 0; corner <= (1 << D); ++corner) {
      std::array<double, D> p{};
      for (int a = 0; a < D; ++a)
        p[a] = corner == (1 << D) ? 0.5 * (box.lo[a] + box.hi[a]) : ((corner >> a) & 1 ? box.hi[a] : box.lo[a]);
      if (fixed_axis >= 0) p[fixed_axis] = level;
      gradient_.evaluate(p.data());
      samples.push_back(gradient_.result().gradient());
    }
  }
  int best_axis = -1;
  double best = 0.0;
  for (int a = 0; a < D; ++a) {
    if (a == fixed_axis) continue;
    double low = 1e300, high = -1e300;
    for (const auto& g : samples) {
      low = std::min(low, g[a]);
      high = std::max(high, g[a]);
    }
    const double m = margin(Interval(low, high));
    if (m > best) {
      best = m;
      best_axis = a;
    }
  }
  return best_axis;
}

template <int D>
void CellQuadrature<D>::line_rule(std::array<double, D> p, int e, const Box<D>& box, double base_weight,
                                  Target target) {
  auto along = [&](double s) {
    p[e] = s;
    return omega_at(p);
  };
  const double a = box.lo[e], b = box.hi[e];
  std::vector<double> roots;
  append_roots(along, a, b, roots, 2);
  std::sort(roots.begin(), roots.end());
  // A boundary on the cell's face (a domain edge on the grid's lattice, a
  // common case) gives omega = 0 exactly at an end, not a sign change. The
  // cell whose adjacent segment is inside takes the surface point, so the
  // neighbour across the face does not take it twice.
  const double first_end = roots.empty() ? b : roots.front(), last_start = roots.empty() ? a : roots.back();
  if (along(b) == 0.0 && along(0.5 * (last_start + b)) > 0) roots.push_back(b);
  if (along(a) == 0.0 && along(0.5 * (a + first_end)) > 0) roots.insert(roots.begin(), a);
  if (target.surface) {
    for (const double root : roots) {
      p[e] = root;
      gradient_.evaluate(p.data());
      const auto g = gradient_.result().gradient();
      double norm = 0.0;
      for (int k = 0; k < D; ++k) norm += g[k] * g[k];
      norm = std::sqrt(norm);
      if (!(norm > 0) || g[e] == 0.0) continue;
      SurfacePoint<D> s{};
      s.x = p;
      s.weight = base_weight * norm / std::abs(g[e]);
      for (int k = 0; k < D; ++k) s.normal[k] = -g[k] / norm;
      target.surface->push_back(s);
    }
  }
  const GaussRule& rule = gauss_legendre(options_.points);
  roots.push_back(b);
  double start = a;
  for (const double end : roots) {
    const double length = end - start;
    if (length > 0 && along(0.5 * (start + end)) >= 0) {
      for (std::size_t k = 0; k < rule.nodes.size(); ++k) {
        p[e] = start + length * rule.nodes[k];
        target.volume->push_back({p, base_weight * length * rule.weights[k]});
      }
    }
    start = end;
  }
}

template class CellQuadrature<2>;
template class CellQuadrature<3>;

}  // namespace sage::solver
