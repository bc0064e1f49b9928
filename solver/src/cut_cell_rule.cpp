#include "cut_cell_rule.hpp"

#include <sage/solver/gauss.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <limits>

namespace sage::solver {

namespace {

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
void append_roots(F&& f, double a, double b, std::vector<double>& roots, int samples) {
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
/// break points.
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

/// A value enclosure that is 0 up to the rounding of an exact zero: the
/// piece vanishes on the whole box (a face of the domain on a cell face).
bool identically_zero(const Interval& v) { return v.lo >= -1e-300 && v.hi <= 1e-300; }

}  // namespace

int touching_sign(const Interval& v) {
  const double slack = 1e-12 * (v.hi - v.lo);
  if (v.lo >= -slack && v.hi > slack) return 1;
  if (v.hi <= slack && v.lo < -slack) return -1;
  return 0;
}

ClassifiedCell classified_cell(const BooleanFormula& restricted,
                               const std::function<Interval(std::uint32_t)>& enclosure) {
  if (restricted.is_constant()) return {restricted.constant_value() ? CellKind::Inside : CellKind::Outside, restricted};
  const BooleanFormula volume =
      restricted.restricted([&](std::size_t p) { return touching_sign(enclosure(static_cast<std::uint32_t>(p))); });
  if (!volume.is_constant()) return {CellKind::Cut, restricted};
  return {volume.constant_value() ? CellKind::Inside : CellKind::Outside, restricted};
}

template <int D>
class CutCellRule<D>::Impl {
 public:
  using Point = std::array<double, D>;
  using Emit = std::function<void(const Point&, double)>;

  explicit Impl(QuadratureOptions options) : options_(options) {}

  const QuadratureCounts& counts() const { return counts_; }

  void append(PieceSource<D>& pieces, const Box<D>& box, const ClassifiedCell& cell,
              std::vector<VolumePoint<D>>& volume, std::vector<SurfacePoint<D>>* surface, bool resolve_base) {
    pieces_ = &pieces;
    resolve_base_ = resolve_base;
    if (inside_.size() < pieces.count()) inside_.resize(pieces.count(), 0);
    volume_ = &volume;
    surface_ = surface;
    scale_ = 0.0;
    for (int a = 0; a < D; ++a) scale_ = std::max(scale_, box.hi[a] - box.lo[a]);
    if (cell.kind == CellKind::Inside) {
      tensor(box, options_.inside_points > 0 ? options_.inside_points : options_.points, nullptr);
      // Faces of the domain on the box's faces (classified_cell()).
      if (surface_ && !cell.formula.is_constant())
        for (const std::uint32_t piece : cell.formula.pieces()) surface_rule(box, cell.formula, piece, 0);
      return;
    }
    if (cell.kind == CellKind::Cut) cut(box, cell.formula, 0);
  }

 private:
  // -- pieces ---------------------------------------------------------------
  double piece_value(std::uint32_t i, const Point& p) { return pieces_->value(i, p); }
  double piece_gradient(std::uint32_t i, const Point& p, Point& g) { return pieces_->gradient(i, p, g); }
  std::array<Interval, D + 1> piece_enclosure(std::uint32_t i, const std::array<Interval, D>& x) {
    return pieces_->enclosure(i, x);
  }
  static std::array<Interval, D> box_intervals(const Box<D>& box) {
    std::array<Interval, D> x{};
    for (int a = 0; a < D; ++a) x[a] = Interval(box.lo[a], box.hi[a]);
    return x;
  }
  /// Whether the formula holds at p (every piece it reads evaluated there).
  bool holds(const BooleanFormula& f, const std::vector<std::uint32_t>& pieces, const Point& p) {
    for (const std::uint32_t i : pieces) inside_[i] = piece_value(i, p) >= 0 ? 1 : 0;
    return f.holds(inside_);
  }

  // -- level functions of the base recursion --------------------------------
  // A level is a function of the point: a piece, or a level evaluated on the
  // root of another along an axis (their crossing), with some coordinates
  // fixed (restricted to a face). Stored in an arena per cell.
  struct Level {
    std::uint32_t piece = 0;     // the body when child < 0
    int child = -1, other = -1;  // else: child evaluated on the root of `other` along `axis`
    int axis = -1;
    double lo = 0, hi = 0;  // where that root is sought (extended beyond by secants)
    unsigned fixed = 0;     // axes fixed at fixed_value
    Point fixed_value{};
    int family = -1;  // restrictions of one monotone level along one axis: they never cross
  };

  int add_level(const Level& l) {
    levels_.push_back(l);
    return static_cast<int>(levels_.size() - 1);
  }
  int restrict_level(int level, int axis, double value, int family) {
    Level l = levels_[static_cast<std::size_t>(level)];
    l.fixed |= 1u << axis;
    l.fixed_value[axis] = value;
    l.family = family;
    return add_level(l);
  }
  int crossing_level(int child, int other, int axis, double lo, double hi) {
    Level l;
    l.child = child;
    l.other = other;
    l.axis = axis;
    l.lo = lo;
    l.hi = hi;
    return add_level(l);
  }

  /// The level's value at p, and its gradient (0 along fixed axes) when asked.
  double level_value(int index, Point p, Point* gradient) {
    const Level l = levels_[static_cast<std::size_t>(index)];
    for (int a = 0; a < D; ++a)
      if (l.fixed & (1u << a)) p[a] = l.fixed_value[a];
    double v = 0.0;
    if (l.child < 0) {
      v = gradient ? piece_gradient(l.piece, p, *gradient) : piece_value(l.piece, p);
    } else {
      p[l.axis] = root_along(l.other, p, l.axis, l.lo, l.hi);
      if (!gradient) {
        v = level_value(l.child, p, nullptr);
      } else {
        Point child{}, other{};
        v = level_value(l.child, p, &child);
        level_value(l.other, p, &other);
        // d root / dx_a = -(d other / dx_a) / (d other / dx_axis).
        const double slope = other[l.axis];
        for (int a = 0; a < D; ++a)
          (*gradient)[a] = slope != 0.0 ? child[a] - child[l.axis] * other[a] / slope : child[a];
        (*gradient)[l.axis] = 0.0;
      }
    }
    if (gradient)
      for (int a = 0; a < D; ++a)
        if (l.fixed & (1u << a)) (*gradient)[a] = 0.0;
    return v;
  }

  /// The root of level `other` along `axis` on the line through p: in
  /// [lo, hi] when it changes sign there, else extrapolated by secants
  /// (exact for planes), so that crossings are smooth functions.
  double root_along(int other, Point p, int axis, double lo, double hi) {
    auto f = [&](double s) {
      p[axis] = s;
      return level_value(other, p, nullptr);
    };
    double a = lo, b = hi, fa = f(a), fb = f(b);
    if (fa == 0.0) return a;
    if (fb == 0.0) return b;
    if ((fa < 0) != (fb < 0)) return bracketed_root(f, a, b, fa, fb);
    const double reach = 4.0 * (hi - lo);
    for (int iteration = 0; iteration < 8 && fb != fa; ++iteration) {
      const double c = std::clamp(b - fb * (b - a) / (fb - fa), lo - reach, hi + reach);
      const double fc = f(c);
      a = b;
      fa = fb;
      b = c;
      fb = fc;
      if (fc == 0.0 || std::abs(b - a) <= 1e-15 * (hi - lo)) break;
    }
    return b;
  }

  /// What a level does over a box of the free axes.
  struct Shape {
    bool may_vanish = true;
    bool vanishes_everywhere = false;
    unsigned monotone = 0;     // axes along which it is strictly monotone
    unsigned independent = 0;  // axes it does not depend on
    Point slope_margin{};      // per axis: the least |d/dx_a| over the box (relative to the largest gradient)
  };

  /// From interval enclosures when the level is a piece with fixed
  /// coordinates (tight for primitives); from samples at the corners and
  /// the centre otherwise, or when `sampled` (deep fields whose derivative
  /// enclosures are too loose).
  Shape shape(int index, const Box<D>& box, unsigned free, bool sampled) {
    const Level& l = levels_[static_cast<std::size_t>(index)];
    Shape s;
    if (l.child < 0 && !sampled) {
      std::array<Interval, D> x = box_intervals(box);
      for (int a = 0; a < D; ++a)
        if (l.fixed & (1u << a)) x[a] = Interval(l.fixed_value[a]);
      const auto e = piece_enclosure(l.piece, x);
      if (e[0].is_nan()) return sampled_shape(index, box, free);
      s.may_vanish = e[0].contains_zero();
      s.vanishes_everywhere = identically_zero(e[0]);
      double largest = 0.0;
      for (int a = 0; a < D; ++a)
        if (free & (1u << a)) largest = std::max(largest, std::max(std::abs(e[a + 1].lo), std::abs(e[a + 1].hi)));
      for (int a = 0; a < D; ++a) {
        if (!(free & (1u << a))) continue;
        const Interval& g = e[a + 1];
        if (g.lo == 0.0 && g.hi == 0.0) s.independent |= 1u << a;
        if (margin(g) > 0.0) {
          s.monotone |= 1u << a;
          s.slope_margin[a] = margin(g) / largest;
        }
      }
      return s;
    }
    return sampled_shape(index, box, free);
  }

  Shape sampled_shape(int index, const Box<D>& box, unsigned free) {
    Shape s;
    const int m = std::popcount(free);
    double low = std::numeric_limits<double>::infinity(), high = -low, largest = 0.0, least = low;
    Point g_low{}, g_high{};
    g_low.fill(std::numeric_limits<double>::infinity());
    g_high.fill(-std::numeric_limits<double>::infinity());
    double half_diagonal = 0.0;
    for (int a = 0; a < D; ++a)
      if (free & (1u << a)) half_diagonal += 0.25 * (box.hi[a] - box.lo[a]) * (box.hi[a] - box.lo[a]);
    half_diagonal = std::sqrt(half_diagonal);
    for (int corner = 0; corner <= (1 << m); ++corner) {
      Point p{};
      int bit = 0;
      for (int a = 0; a < D; ++a) {
        p[a] = 0.5 * (box.lo[a] + box.hi[a]);
        if (!(free & (1u << a)) || corner == (1 << m)) continue;
        p[a] = (corner >> bit++) & 1 ? box.hi[a] : box.lo[a];
      }
      Point g{};
      const double v = level_value(index, p, &g);
      low = std::min(low, v);
      high = std::max(high, v);
      least = std::min(least, std::abs(v));
      double norm = 0.0;
      for (int a = 0; a < D; ++a) {
        if (!(free & (1u << a))) continue;
        g_low[a] = std::min(g_low[a], g[a]);
        g_high[a] = std::max(g_high[a], g[a]);
        norm += g[a] * g[a];
      }
      largest = std::max(largest, std::sqrt(norm));
    }
    // No sign change at the samples and far from zero by the slopes seen:
    // taken not to vanish (a level that does is still searched for roots).
    s.may_vanish = !(low > 0 || high < 0) || least <= largest * half_diagonal;
    for (int a = 0; a < D; ++a) {
      if (!(free & (1u << a))) continue;
      const Interval g(g_low[a], g_high[a]);
      if (std::max(std::abs(g.lo), std::abs(g.hi)) <= 1e-13 * largest) s.independent |= 1u << a;
      if (margin(g) > 0.0) {
        s.monotone |= 1u << a;
        s.slope_margin[a] = margin(g) / largest;
      }
    }
    return s;
  }

  // -- rules ----------------------------------------------------------------
  /// Tensor Gauss points of the box; with a formula, only where it holds.
  void tensor(const Box<D>& box, int points, const BooleanFormula* mask) {
    const GaussRule& rule = gauss_legendre(points);
    std::vector<std::uint32_t> pieces;
    if (mask) pieces = mask->pieces();
    int total = 1;
    for (int a = 0; a < D; ++a) total *= points;
    for (int k = 0; k < total; ++k) {
      VolumePoint<D> p{};
      p.weight = 1.0;
      int rest = k;
      for (int a = 0; a < D; ++a) {
        const auto n = static_cast<std::size_t>(rest % points);
        rest /= points;
        const double width = box.hi[a] - box.lo[a];
        p.x[a] = box.lo[a] + width * rule.nodes[n];
        p.weight *= width * rule.weights[n];
      }
      if (mask && !holds(*mask, pieces, p.x)) continue;
      volume_->push_back(p);
      if (mask) ++counts_.masked_points;
    }
  }

  /// The formula restricted to `box` by the pieces' enclosures there, and
  /// the enclosures of the pieces it still reads.
  struct Restricted {
    BooleanFormula formula;
    std::vector<std::uint32_t> pieces;
    std::vector<std::array<Interval, D + 1>> enclosure;  // per entry of pieces
  };
  Restricted restrict_to(const Box<D>& box, const BooleanFormula& formula) {
    const auto x = box_intervals(box);
    Restricted r;
    const std::vector<std::uint32_t> before = formula.pieces();
    std::vector<std::array<Interval, D + 1>> enclosures(before.size());
    for (std::size_t k = 0; k < before.size(); ++k) {
      enclosures[k] = piece_enclosure(before[k], x);
      inside_[before[k]] = static_cast<char>(sign_of(enclosures[k][0]));
    }
    r.formula = formula.restricted([&](std::size_t p) { return int{static_cast<signed char>(inside_[p])}; });
    r.pieces = r.formula.pieces();
    for (const std::uint32_t p : r.pieces)
      r.enclosure.push_back(
          enclosures[static_cast<std::size_t>(std::lower_bound(before.begin(), before.end(), p) - before.begin())]);
    return r;
  }

  /// A height direction for all `levels` over the box, or -1.
  int height_direction(const std::vector<Shape>& shapes, unsigned free) {
    int best_axis = -1;
    double best = -1.0;
    for (int a = 0; a < D; ++a) {
      if (!(free & (1u << a))) continue;
      double score = std::numeric_limits<double>::infinity();
      bool ok = true;
      for (const Shape& s : shapes) {
        if (!s.may_vanish) continue;
        if (s.monotone & (1u << a)) {
          score = std::min(score, s.slope_margin[a]);
        } else if (!(s.independent & (1u << a))) {
          ok = false;
        } else if (!resolve_base_) {
          score = 0.0;  // a wall along the lines: a jump across an unbroken base
        }
      }
      if (ok && score > best) {
        best = score;
        best_axis = a;
      }
    }
    return best_axis;
  }

  /// The axis along which a level is monotone with the widest margin, or -1.
  static int steepest_axis(const Shape& s) {
    int best = -1;
    for (int a = 0; a < D; ++a)
      if ((s.monotone & (1u << a)) && (best < 0 || s.slope_margin[a] > s.slope_margin[best])) best = a;
    return best;
  }

  void cut(const Box<D>& box, const BooleanFormula& formula, int depth) {
    const Restricted r = restrict_to(box, formula);
    // Planar pieces need no more nodes than the integrand's degree asks;
    // curved ones get options_.curved_extra more (their roots and normals
    // vary along the base).
    points_ = options_.points;
    for (const std::uint32_t p : r.pieces)
      if (!pieces_->planar(p)) points_ = options_.points + options_.curved_extra;
    if (r.formula.is_constant()) {
      if (r.formula.constant_value()) tensor(box, points_, nullptr);
      return;
    }
    // One piece: one pass gives the volume and the surface (the lines
    // along its height direction carry both). Several: the volume in a
    // direction where all are monotone, then each piece's surface in its own.
    levels_.clear();
    std::vector<int> piece_levels;
    for (const std::uint32_t p : r.pieces) {
      Level l;
      l.piece = p;
      piece_levels.push_back(add_level(l));
    }
    const unsigned all = (1u << D) - 1;
    std::vector<Shape> shapes;
    for (const int l : piece_levels) shapes.push_back(shape(l, box, all, false));
    int e = height_direction(shapes, all);
    if (e < 0 && depth > 0) {
      shapes.clear();
      for (const int l : piece_levels) shapes.push_back(shape(l, box, all, true));
      e = height_direction(shapes, all);
    }
    if (e < 0) {
      if (depth >= options_.max_depth) {
        ++counts_.masked_boxes;
        tensor(box, points_, &r.formula);
        return;
      }
      for (int child = 0; child < (1 << D); ++child) cut(half(box, child, all), r.formula, depth + 1);
      return;
    }
    // The single piece's surface comes with the volume's lines when they
    // cross it (not when it is a wall parallel to them).
    const bool single = r.pieces.size() == 1 && (shapes[0].monotone & (1u << e)) && resolve_base_;
    volume_rule(box, r, piece_levels, shapes, e, single);
    if (surface_ && !single && resolve_base_)
      for (std::size_t k = 0; k < r.pieces.size(); ++k) surface_rule(box, r.formula, r.pieces[k], depth);
  }

  /// Child `child` of the box split in halves along the axes in `axes`.
  static Box<D> half(const Box<D>& box, int child, unsigned axes) {
    Box<D> part = box;
    int bit = 0;
    for (int a = 0; a < D; ++a) {
      if (!(axes & (1u << a))) continue;
      const double mid = 0.5 * (box.lo[a] + box.hi[a]);
      if (child & (1 << bit++)) {
        part.lo[a] = mid;
      } else {
        part.hi[a] = mid;
      }
    }
    return part;
  }

  /// The base levels of height direction e: the pieces on the bottom and
  /// top faces, the e-independent pieces, and the crossings of the pieces
  /// monotone in e.
  std::vector<int> base_levels(const Box<D>& box, const std::vector<int>& piece_levels,
                               const std::vector<Shape>& shapes, int e) {
    std::vector<int> out;
    std::vector<int> monotone;
    for (std::size_t k = 0; k < piece_levels.size(); ++k) {
      const int l = piece_levels[k];
      if (shapes[k].independent & (1u << e)) {
        out.push_back(restrict_level(l, e, box.lo[e], -1));
        continue;
      }
      monotone.push_back(l);
      const int family = next_family_++;
      for (const double face : {box.lo[e], box.hi[e]}) out.push_back(restrict_level(l, e, face, family));
    }
    for (std::size_t i = 0; i < monotone.size(); ++i)
      for (std::size_t j = i + 1; j < monotone.size(); ++j)
        out.push_back(crossing_level(monotone[i], monotone[j], e, box.lo[e], box.hi[e]));
    return out;
  }

  void volume_rule(const Box<D>& box, const Restricted& r, const std::vector<int>& piece_levels,
                   const std::vector<Shape>& shapes, int e, bool with_surface) {
    const std::vector<int> levels = resolve_base_ ? base_levels(box, piece_levels, shapes, e) : std::vector<int>{};
    std::vector<std::uint32_t> along;  // pieces whose roots split the lines
    for (std::size_t k = 0; k < r.pieces.size(); ++k)
      if (!(shapes[k].independent & (1u << e))) along.push_back(r.pieces[k]);
    const unsigned base = ((1u << D) - 1) & ~(1u << e);
    const bool positive = r.formula.holds([](std::size_t) { return true; });
    smooth_rule(box, base, levels, 0, [&](const Point& x, double w) {
      Point p = x;
      const double a = box.lo[e], b = box.hi[e];
      std::vector<double> roots;
      for (const std::uint32_t i : along)
        append_roots(
            [&](double s) {
              p[e] = s;
              return piece_value(i, p);
            },
            a, b, roots, 2);
      std::sort(roots.begin(), roots.end());
      if (with_surface && surface_) line_surface(p, e, a, b, roots, r.pieces[0], positive, w);
      const GaussRule& rule = gauss_legendre(points_);
      roots.push_back(b);
      double start = a;
      for (const double end : roots) {
        const double length = end - start;
        if (length > 0) {
          p[e] = 0.5 * (start + end);
          if (holds(r.formula, r.pieces, p)) {
            for (std::size_t k = 0; k < rule.nodes.size(); ++k) {
              p[e] = start + length * rule.nodes[k];
              volume_->push_back({p, w * length * rule.weights[k]});
            }
          }
        }
        start = end;
      }
    });
  }

  /// Surface points of the single piece on one line of the volume rule:
  /// its roots, and its zeros at the line's ends when the domain's side of
  /// that end lies in the box (so that a face on a cell face is counted
  /// once). `positive`: the domain is where the piece is positive (else
  /// the formula is its negation).
  void line_surface(Point p, int e, double a, double b, std::vector<double> roots, std::uint32_t piece, bool positive,
                    double w) {
    p[e] = b;
    const bool at_b = piece_value(piece, p) == 0.0;
    p[e] = a;
    const bool at_a = piece_value(piece, p) == 0.0;
    const double first_end = roots.empty() ? b : roots.front(), last_start = roots.empty() ? a : roots.back();
    auto inside_at = [&](double s) {
      p[e] = s;
      const double v = piece_value(piece, p);
      return positive ? v > 0 : v < 0;
    };
    if (at_b && inside_at(0.5 * (last_start + b))) roots.push_back(b);
    if (at_a && inside_at(0.5 * (a + first_end))) roots.insert(roots.begin(), a);
    for (const double root : roots) {
      p[e] = root;
      Point g{};
      piece_gradient(piece, p, g);
      emit_surface(p, g, e, w, !positive);
    }
  }

  /// A surface point at p on a piece of gradient g (towards the piece's
  /// inside), reached from the base along e with base weight w; `flip`
  /// when the domain lies on the piece's outside.
  void emit_surface(const Point& p, const Point& g, int e, double w, bool flip) {
    double norm = 0.0;
    for (int k = 0; k < D; ++k) norm += g[k] * g[k];
    norm = std::sqrt(norm);
    if (!(norm > 0) || g[e] == 0.0) return;
    SurfacePoint<D> s{};
    s.x = p;
    s.weight = w * norm / std::abs(g[e]);
    for (int k = 0; k < D; ++k) s.normal[k] = (flip ? g[k] : -g[k]) / norm;
    surface_->push_back(s);
  }

  /// The surface of piece `piece` where the formula changes across it,
  /// in the piece's own height direction.
  void surface_rule(const Box<D>& box, const BooleanFormula& formula, std::uint32_t piece, int depth) {
    const Restricted r = restrict_to(box, formula);
    if (depth == 0) points_ = options_.points + (pieces_->planar(piece) ? 0 : options_.curved_extra);
    if (!std::binary_search(r.pieces.begin(), r.pieces.end(), piece)) return;
    levels_.clear();
    Level own;
    own.piece = piece;
    const int level = add_level(own);
    const unsigned all = (1u << D) - 1;
    int e = steepest_axis(shape(level, box, all, false));
    if (e < 0 && depth > 0) e = steepest_axis(shape(level, box, all, true));
    if (e < 0) {
      if (depth >= options_.max_depth) {
        ++counts_.unresolved_surface;
        return;
      }
      for (int child = 0; child < (1 << D); ++child) surface_rule(half(box, child, all), r.formula, piece, depth + 1);
      return;
    }
    std::vector<int> levels;
    const int family = next_family_++;
    for (const double face : {box.lo[e], box.hi[e]}) levels.push_back(restrict_level(level, e, face, family));
    for (const std::uint32_t other : r.pieces) {
      if (other == piece) continue;
      Level l;
      l.piece = other;
      levels.push_back(crossing_level(add_level(l), level, e, box.lo[e], box.hi[e]));
    }
    const double step = 1e-7 * scale_;
    const unsigned base = all & ~(1u << e);
    smooth_rule(box, base, levels, 0, [&](const Point& x, double w) {
      Point p = x;
      const double a = box.lo[e], b = box.hi[e];
      auto along = [&](double t) {
        p[e] = t;
        return piece_value(piece, p);
      };
      std::vector<double> roots;
      append_roots(along, a, b, roots, 2);
      if (along(a) == 0.0) roots.insert(roots.begin(), a);
      if (along(b) == 0.0) roots.push_back(b);
      for (const double root : roots) {
        p[e] = root;
        Point g{};
        piece_gradient(piece, p, g);
        double norm = 0.0;
        for (int k = 0; k < D; ++k) norm += g[k] * g[k];
        norm = std::sqrt(norm);
        if (!(norm > 0)) continue;
        // Does the domain change across the piece here? Read the formula a
        // step off the surface on either side.
        Point plus = p, minus = p;
        for (int k = 0; k < D; ++k) {
          plus[k] += step * g[k] / norm;
          minus[k] -= step * g[k] / norm;
        }
        const bool in_plus = holds(r.formula, r.pieces, plus), in_minus = holds(r.formula, r.pieces, minus);
        if (in_plus == in_minus) continue;
        // At an end of the line, only the box on the domain's side counts it.
        const double inward_e = in_plus ? g[e] : -g[e];
        if ((root == a && !(inward_e > 0)) || (root == b && !(inward_e < 0))) continue;
        emit_surface(p, g, e, w, !in_plus);
      }
    });
  }

  /// The roots of the levels along `axis` on the line through p, in (lo,
  /// hi), each found between `samples` steps.
  std::vector<double> roots_along(const std::vector<int>& levels, Point p, int axis, double lo, double hi,
                                  int samples) {
    std::vector<double> roots;
    for (const int l : levels)
      append_roots(
          [&](double t) {
            p[axis] = t;
            return level_value(l, p, nullptr);
          },
          lo, hi, roots, samples);
    return roots;
  }

  /// Integrates over the free axes of `box`, calling emit(x, w) with the
  /// free coordinates of x set, so that what emit integrates is smooth
  /// between the zero sets of `levels`.
  void smooth_rule(const Box<D>& box, unsigned free, const std::vector<int>& levels, int depth, const Emit& emit) {
    std::vector<int> kept;
    std::vector<Shape> shapes;
    for (const int l : levels) {
      const Shape s = shape(l, box, free, false);
      if (!s.may_vanish || s.vanishes_everywhere) continue;
      kept.push_back(l);
      shapes.push_back(s);
    }
    const int m = std::popcount(free);
    if (m == 1) {
      const int t = std::countr_zero(free);
      Point p{};
      gauss_on_pieces(box.lo[t], box.hi[t], roots_along(kept, p, t, box.lo[t], box.hi[t], 4), points_,
                      [&](double s, double w) {
                        p[t] = s;
                        emit(p, w);
                      });
      return;
    }
    if (kept.empty()) return tensor_emit(box, free, emit);
    int s = height_direction(shapes, free);
    if (s < 0 && depth > 0) {
      shapes.clear();
      for (const int l : kept) shapes.push_back(shape(l, box, free, true));
      s = height_direction(shapes, free);
    }
    if (s < 0) {
      if (depth >= options_.max_depth) return tensor_emit(box, free, emit);
      for (int child = 0; child < (1 << m); ++child) smooth_rule(half(box, child, free), free, kept, depth + 1, emit);
      return;
    }
    // One dimension down: the kept levels on the two faces across s, and
    // where two of them cross.
    std::vector<int> sub;
    std::vector<int> monotone;
    for (std::size_t k = 0; k < kept.size(); ++k) {
      if (shapes[k].independent & (1u << s)) {
        sub.push_back(restrict_level(kept[k], s, box.lo[s], -1));
        continue;
      }
      monotone.push_back(kept[k]);
      const int family = next_family_++;
      for (const double face : {box.lo[s], box.hi[s]}) sub.push_back(restrict_level(kept[k], s, face, family));
    }
    for (std::size_t i = 0; i < monotone.size(); ++i)
      for (std::size_t j = i + 1; j < monotone.size(); ++j) {
        const int fi = levels_[static_cast<std::size_t>(monotone[i])].family;
        if (fi >= 0 && fi == levels_[static_cast<std::size_t>(monotone[j])].family) continue;
        sub.push_back(crossing_level(monotone[i], monotone[j], s, box.lo[s], box.hi[s]));
      }
    smooth_rule(box, free & ~(1u << s), sub, depth, [&](const Point& x, double w) {
      Point p = x;
      gauss_on_pieces(box.lo[s], box.hi[s], roots_along(monotone, p, s, box.lo[s], box.hi[s], 2), points_,
                      [&](double t, double ws) {
                        p[s] = t;
                        emit(p, w * ws);
                      });
    });
  }

  /// Tensor Gauss points over the free axes.
  void tensor_emit(const Box<D>& box, unsigned free, const Emit& emit) {
    const GaussRule& rule = gauss_legendre(points_);
    const int q = points_, m = std::popcount(free);
    int total = 1;
    for (int k = 0; k < m; ++k) total *= q;
    for (int k = 0; k < total; ++k) {
      Point p{};
      double w = 1.0;
      int rest = k;
      for (int a = 0; a < D; ++a) {
        if (!(free & (1u << a))) continue;
        const auto n = static_cast<std::size_t>(rest % q);
        rest /= q;
        const double width = box.hi[a] - box.lo[a];
        p[a] = box.lo[a] + width * rule.nodes[n];
        w *= width * rule.weights[n];
      }
      emit(p, w);
    }
  }

  PieceSource<D>* pieces_ = nullptr;
  QuadratureOptions options_;
  std::vector<char> inside_;  // per piece, scratch for formulas
  std::vector<Level> levels_;
  int next_family_ = 0;
  int points_ = 1;            // Gauss nodes per direction in the box being cut
  bool resolve_base_ = true;  // break the base where the lines' integrals are not smooth
  QuadratureCounts counts_;
  double scale_ = 1.0;
  std::vector<VolumePoint<D>>* volume_ = nullptr;
  std::vector<SurfacePoint<D>>* surface_ = nullptr;
};

template <int D>
CutCellRule<D>::CutCellRule(QuadratureOptions options) : impl_(std::make_unique<Impl>(options)) {}

template <int D>
CutCellRule<D>::~CutCellRule() = default;

template <int D>
CutCellRule<D>::CutCellRule(CutCellRule&&) noexcept = default;

template <int D>
void CutCellRule<D>::append(PieceSource<D>& pieces, const Box<D>& box, const ClassifiedCell& cell,
                            std::vector<VolumePoint<D>>& volume, std::vector<SurfacePoint<D>>* surface,
                            bool resolve_base) {
  impl_->append(pieces, box, cell, volume, surface, resolve_base);
}

template <int D>
const QuadratureCounts& CutCellRule<D>::counts() const {
  return impl_->counts();
}

template class CutCellRule<2>;
template class CutCellRule<3>;

}  // namespace sage::solver
