#include <sage/evaluator.hpp>
#include <sage/geometry/polygon_brep.hpp>
#include <sage/geometry/well_formedness.hpp>

#include <algorithm>
#include <array>
#include <sstream>
#include <vector>

namespace sage::geometry {

Certificate certify_no_spurious_zeros(const Expr& field, const PolygonSet& polygons, const Bounds& bounds, double band,
                                      std::size_t budget) {
  const Tape tape(field, 2);
  const PolygonClassifier edges(polygons);  // its box test finds edges near a box
  Certificate c;
  c.band = band;
  using Box = std::array<Interval, 2>;
  std::vector<Box> level{{Interval(bounds.min[0], bounds.max[0]), Interval(bounds.min[1], bounds.max[1])}};
  bool failed = false;
  Box failure{};
  while (!level.empty() && !failed) {
    if (c.boxes + level.size() > budget) break;
    c.boxes += level.size();
    std::vector<char> split(level.size(), 0);
#pragma omp parallel
    {
      Evaluator<Interval> eval(tape);
#pragma omp for schedule(dynamic, 64)
      for (std::size_t i = 0; i < level.size(); ++i) {
        const Box& b = level[i];
        eval.evaluate_with(b.data());
        if (!eval.result().contains_zero()) continue;  // proven: no zero here
        const double width = std::max(b[0].width(), b[1].width());
        const Box grown{Interval(b[0].lo - band, b[0].hi + band), Interval(b[1].lo - band, b[1].hi + band)};
        if (width <= band && edges.classify_box(grown.data()).width() > 0) continue;  // within the band of an edge
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
      if (split[i] == 2) {
        failed = true;
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
    text << "NOT well-formed: omega may vanish away from the boundary near (" << failure[0].mid() << ", "
         << failure[1].mid() << ")";
  } else if (!level.empty()) {
    text << "not certified: gave up after " << c.boxes << " interval boxes";
  } else {
    c.certified = true;
    text << "certified well-formed: no zeros of omega farther than " << band
         << " from the boundary within the bounds (interval arithmetic, " << c.boxes << " boxes)";
  }
  c.text = text.str();
  return c;
}

}  // namespace sage::geometry
