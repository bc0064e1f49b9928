#include <sage/expression/derivative.hpp>
#include <sage/expression/normalize.hpp>

namespace sage {

Expr gradient_norm_squared(const Expr& f, int dimension) {
  Expr sum = 0.0;
  for (const Expr& g : gradient(f, dimension)) sum += square(g);
  return sum;
}

Expr normalize(const Expr& f, int dimension) { return f / sqrt(square(f) + gradient_norm_squared(f, dimension)); }

}  // namespace sage
