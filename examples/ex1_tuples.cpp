//                         sage example 1: tuples
//
// Sample runs:  ex1_tuples
//
// Description:  Builds the normalized disk (1 - x^2 - y^2) / 2 as an
//               expression, compiles it to a tape, and evaluates it with
//               three scalar types: a double (the value), a tuple (value
//               and every partial derivative through order 3) and an
//               interval (a guaranteed range over a box). This is the
//               core loop of sage; every later example builds on it.

#include <sage/expression/expression.hpp>
#include <sage/tape/evaluator.hpp>

#include <cmath>
#include <cstdio>

int main() {
  using namespace sage;

  // 1. Build the field as an expression graph. It is >= 0 inside the unit
  //    disk, 0 on the circle and |grad| = 1 there: normalized.
  const Expr x = Expr::x(), y = Expr::y();
  const Expr disk = (1.0 - square(x) - square(y)) * 0.5;

  // 2. Compile it once into a tape (2 variables).
  const Tape tape(disk, 2);

  // 3. A double: the value at a point.
  Evaluator<double> values(tape);
  std::printf("omega(0.6, 0.8)          = %g  (on the circle)\n", values.at({0.6, 0.8}));

  // 4. A tuple: value and all partials through order 3 at the same point.
  //    derivative({i, j}) is d^(i+j) omega / dx^i dy^j.
  Evaluator<Tuple<2, 3>> tuples(tape);
  const Tuple<2, 3> t = tuples.at({0.6, 0.8});
  std::printf("grad omega               = (%g, %g), |grad| = 1 on the boundary\n", t.derivative({1, 0}),
              t.derivative({0, 1}));
  std::printf("d2/dx2, d2/dxdy, d3/dx3  = %g, %g, %g\n", t.derivative({2, 0}), t.derivative({1, 1}),
              t.derivative({3, 0}));

  // 5. An interval: an enclosure of omega over the box [0, 0.5] x [0, 0.5].
  //    0 is not inside it, which proves the box holds no boundary point.
  Evaluator<Interval> ranges(tape);
  const Interval box[2] = {{0.0, 0.5}, {0.0, 0.5}};
  ranges.evaluate_with(box);
  std::printf("omega over [0,.5]x[0,.5] in [%g, %g]\n", ranges.result().lo, ranges.result().hi);

  // 6. Check: the gradient (-x, -y) has length 1 on the circle, the second
  //    derivative d2/dx2 is -1, the third 0, and the box is proved inside.
  const bool right = std::abs(std::hypot(t.derivative({1, 0}), t.derivative({0, 1})) - 1.0) < 1e-15 &&
                     std::abs(t.derivative({2, 0}) + 1.0) < 1e-15 && t.derivative({3, 0}) == 0.0 &&
                     ranges.result().lo > 0.0;
  return right ? 0 : 1;
}
