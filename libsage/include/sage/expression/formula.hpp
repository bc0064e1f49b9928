#pragma once
// User formulas: a small expression language parsed into the expression
// graph, enough to write every primitive of paper 003's table.
//
//   numbers      1, 0.25, 1e-3          constants  pi, e
//   variables    x, y (and z in 3D)
//   operators    + - * / ^  (^ binds tightest and is right-associative;
//                -x^2 is -(x^2))
//   functions    sqrt exp log sin cos abs  (one argument)
//                min max pow               (two arguments)
//
// Integer exponents become exact integer powers (x^500 is fine, and
// (-2)^3 = -8); other exponents need a base >= 0; a non-constant exponent
// a^b is exp(b log a).
//
// Errors throw FormulaError with the 1-based column of the offending
// character and what was expected there.

#include <sage/expression/expression.hpp>

#include <stdexcept>
#include <string>

namespace sage {

class FormulaError : public std::runtime_error {
 public:
  FormulaError(std::size_t column, const std::string& message)
      : std::runtime_error("column " + std::to_string(column) + ": " + message), column_(column) {}
  std::size_t column() const { return column_; }

 private:
  std::size_t column_;
};

/// Parses `text` into an expression in `dimension` (2 or 3) variables.
Expr parse_formula(const std::string& text, int dimension);

}  // namespace sage
