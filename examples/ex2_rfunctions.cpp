//                         sage example 2: R-functions
//
// Sample runs:  ex2_rfunctions
//
// Description:  Intersects the halfplanes x >= 0 and y >= 0 with each
//               R-function system and prints what paper 004 (sec. 2)
//               promises: the gradient length on the boundary away from
//               the corner, the second normal derivative there, and the
//               value and gradient at the corner itself. Adds to example 1:
//               R-function nodes and the choice of system.

#include <sage/expression/expression.hpp>
#include <sage/tape/evaluator.hpp>

#include <cmath>
#include <cstdio>
#include <string>

int main() {
  using namespace sage;
  const Expr x = Expr::x(), y = Expr::y();

  bool right = true;
  std::printf("%-12s %12s %14s %22s\n", "system", "|grad| at", "d2/dx2 at", "corner value, grad");
  std::printf("%-12s %12s %14s %22s\n", "", "(0, 2)", "(0, 2)", "at (0, 0)");
  for (const char* name : {"minmax", "r0", "ralpha:0.5", "ralpha:var", "rp:2", "rp:4", "rm:2"}) {
    // 1. The conjunction x AND y with this system, as one expression node.
    const RSystem system = RSystem::parse(name);
    const Tape tape(r_and(x, y, system), 2);

    // 2. On the boundary piece x = 0, y > 0 the normal is the x direction.
    //    (rm:2 is not normalized: its |grad| there is y^2 = 4.)
    Evaluator<Tuple<2, 2>> eval(tape);
    const Tuple<2, 2> edge = eval.at({0.0, 2.0});
    const double grad = std::hypot(edge.derivative({1, 0}), edge.derivative({0, 1}));

    // 3. At the corner: R0^m vanishes with all its first derivatives.
    const Tuple<2, 2> corner = eval.at({0.0, 0.0});
    std::printf("%-12s %12.6f %14.6f %10.3g, (%g, %g)\n", name, grad, edge.derivative({2, 0}), corner.value(),
                corner.derivative({1, 0}), corner.derivative({0, 1}));
    // 4. Check the promises: every system but rm:2 is normalized on the edge.
    const bool normalized = std::string(name) == "rm:2" || std::abs(grad - 1.0) < 1e-12;
    const bool flat = std::string(name) != "rp:4" || std::abs(edge.derivative({2, 0})) < 1e-12;
    right = right && normalized && flat;
  }
  std::printf(
      "\nrp:4 is normalized to order 3, so its d2/dx2 on the edge is 0; r0 only to order 1.\n"
      "minmax has d2/dx2 = 0 too, but no derivative at all across x = y.\n");
  return right ? 0 : 1;
}
