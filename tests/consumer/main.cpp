// Uses the installed sage: a normalized disk, its value and gradient at a
// boundary point. Exits 0 when |grad| = 1 there.
#include <sage/expression/primitives.hpp>
#include <sage/tape/evaluator.hpp>

#include <cmath>
#include <cstdio>

int main() {
  const sage::Expr disk = sage::ball({0, 0, 0}, 2.0, 2);
  const sage::Tape tape(disk, 2);
  sage::Evaluator<sage::Tuple<2, 1>> eval(tape);
  const auto t = eval.at({2.0, 0.0});
  const double norm = std::hypot(t.c[1], t.c[2]);
  std::printf("omega = %g, |grad| = %g\n", t.value(), norm);
  return std::abs(t.value()) < 1e-12 && std::abs(norm - 1.0) < 1e-12 ? 0 : 1;
}
