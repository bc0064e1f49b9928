#include <sage/solver/boundary_structure.hpp>

#include <stdexcept>

namespace sage::solver {

Expr transfinite_interpolation(const std::vector<Expr>& fields, const std::vector<Expr>& data) {
  if (fields.size() != data.size() || fields.empty())
    throw std::invalid_argument("transfinite interpolation needs one field per data piece");
  if (fields.size() == 1) return data[0];
  Expr numerator = 0.0, denominator = 0.0;
  for (std::size_t k = 0; k < fields.size(); ++k) {
    Expr product = 1.0;
    for (std::size_t l = 0; l < fields.size(); ++l)
      if (l != k) product = product * square(fields[l]);
    numerator = numerator + data[k] * product;
    denominator = denominator + product;
  }
  return div_safe(numerator, denominator);
}

}  // namespace sage::solver
