#include <sage/evaluator.hpp>
#include <sage/geometry/polygon_brep.hpp>
#include <sage/geometry/well_formedness.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <vector>

namespace sage::geometry {

Certificate certify_no_spurious_zeros(const Expr& field, const PolygonSet& polygons, const Bounds& bounds, double band,
                                      std::size_t budget) {
  const Tape tape(field, 2);
  const PolygonClassifier edges(polygons);  // its box test finds edges near a box
  Certificate c;
  // A box at most `band` wide that meets an edge once grown by `band` lies
  // within the grown box's diagonal, 3 sqrt(2) band, of that edge.
  c.band = 3 * std::sqrt(2.0) * band;
  using Box = std::array<Interval, 2>;
  std::vector<Box> level{{Interval(bounds.min[0], bounds.max[0]), Interval(bounds.min[1], bounds.max[1])}};
  bool failed = false, proven = false;
  Box failure{};
  while (!level.empty() && !failed) {
    if (c.boxes + level.size() > budget) break;
    c.boxes += level.size();
    std::vector<char> split(level.size(), 0);
#pragma omp parallel
    {
      Evaluator<Interval> eval(tape);
      Evaluator<double> values(tape);
      // Does omega take both signs (or 0) at the corners and centre of b?
      auto changes_sign = [&values](const Box& b) {
        int positive = 0, negative = 0;
        for (double fx : {0.0, 0.5, 1.0})
          for (double fy : {0.0, 0.5, 1.0}) {
            const double v = values.at({b[0].lo + fx * b[0].width(), b[1].lo + fy * b[1].width(), 0.0});
            positive += v >= 0;
            negative += v <= 0;
          }
        return positive > 0 && negative > 0;
      };
#pragma omp for schedule(dynamic, 64)
      for (std::size_t i = 0; i < level.size(); ++i) {
        const Box& b = level[i];
        eval.evaluate_with(b.data());
        const Interval range = eval.result();
        if (!range.is_nan() && !range.contains_zero()) continue;  // proven: no zero here
        const double width = std::max(b[0].width(), b[1].width());
        const Box grown{Interval(b[0].lo - band, b[0].hi + band), Interval(b[1].lo - band, b[1].hi + band)};
        const bool near_edge = edges.edge_meets(grown.data());
        if (width <= band && near_edge) continue;  // within 3 sqrt(2) band of an edge
        // Away from the edges: a sign change between sample points proves
        // a zero there (omega is continuous and the box meets no edge).
        if (!near_edge && changes_sign(b)) {
          split[i] = 3;
          continue;
        }
        // Interval bounds overestimate in proportion to the box size, so a
        // box away from the edges is split further before it counts as a
        // possible zero.
        if (width > band / 1024) {
          split[i] = 1;
          continue;
        }
        split[i] = 2;  // a possible zero away from every edge
      }
    }
    std::vector<Box> next;
    for (std::size_t i = 0; i < level.size(); ++i) {
      if (split[i] >= 2) {
        failed = true;
        proven = split[i] == 3;
        failure = level[i];
        break;
      }
      if (split[i] != 1) continue;
      const Box& b = level[i];
      const double mx = b[0].mid(), my = b[1].mid();
      next.push_back({Interval(b[0].lo, mx), Interval(b[1].lo, my)});
      next.push_back({Interval(mx, b[0].hi), Interval(b[1].lo, my)});
      next.push_back({Interval(b[0].lo, mx), Interval(my, b[1].hi)});
      next.push_back({Interval(mx, b[0].hi), Interval(my, b[1].hi)});
    }
    level = std::move(next);
  }
  std::ostringstream text;
  text.precision(9);
  if (failed) {
    text << "NOT well-formed: omega " << (proven ? "vanishes" : "may vanish") << " away from the boundary near ("
         << failure[0].mid() << ", " << failure[1].mid() << ")";
  } else if (!level.empty()) {
    text << "not certified: gave up after " << c.boxes << " interval boxes";
  } else {
    c.certified = true;
    text << "certified well-formed: no zeros of omega farther than " << c.band
         << " from the boundary within the bounds (interval arithmetic, " << c.boxes << " boxes)";
  }
  c.text = text.str();
  return c;
}

}  // namespace sage::geometry
