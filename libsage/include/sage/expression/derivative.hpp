#pragma once
// Symbolic differentiation of expressions. The derivative of an expression
// is an expression over the same nodes (shared, not copied), so a gradient
// costs a few times the original graph, and its tape evaluates with double,
// Tuple or Interval like any other.
//
// Rules follow scalar.hpp's singular-point conventions: the derivative of
// sqrt(u) is div_safe(u', 2 sqrt(u)), zero where u = 0, matching tuples;
// min/max use step(), so at a tie they average the two arguments'
// derivatives, again matching tuples. R-function nodes are differentiated
// through their formula (rfunction.hpp instantiated with Expr).

#include <sage/expression/expression.hpp>

#include <vector>

namespace sage {

/// d f / d x_var (var = 0, 1, 2 for x, y, z).
Expr derivative(const Expr& f, int var);

/// The first `dimension` partial derivatives of f, sharing one memo.
std::vector<Expr> gradient(const Expr& f, int dimension);

/// The R-function node `f` (RAnd or ROr) written out with elementary operations.
Expr expand_rfunction(const Expr& f);

}  // namespace sage
