#pragma once
// The normalization operator (paper 004, conclusions; FORMULAS.md):
//
//     normalize(f) = f / sqrt(f^2 + |grad f|^2)
//
// Same sign and zero set as f, and |grad| = 1 on f = 0 wherever grad f != 0:
// normalized to first order. The result is bounded by 1 in magnitude and
// smooth wherever f is. grad f comes from symbolic differentiation, so the
// normalized field has derivatives of every order like any expression.

#include <sage/expression/expression.hpp>

namespace sage {

/// normalize(f) in `dimension` variables (the gradient uses x..x_dim-1).
Expr normalize(const Expr& f, int dimension);

/// |grad f|^2 as an expression.
Expr gradient_norm_squared(const Expr& f, int dimension);

}  // namespace sage
