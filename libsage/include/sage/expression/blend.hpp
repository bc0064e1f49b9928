#pragma once
// Soft blending with the Lipschitz property (paper 000; FORMULAS.md,
// "Soft blending"). Arguments are fields >= 0 inside; for exact signed
// distances (Lipschitz constant 1) every result below is Lipschitz-1
// again, because every blend function has -1 <= fb'(x) <= 0 for x >= 0:
//
//     union        max(f1, f2) + fb(|f1 - f2|, n)
//     intersection min(f1, f2) - fb(|f1 - f2|, n)
//     difference   min(f1, -f2) - fb(|f1 + f2|, n)
//
// The six blend functions of the paper, x >= 0, amount n >= 0:
//
// | fb | formula                                   | C1 on f1=f2 | local    |
// |----|-------------------------------------------|-------------|----------|
// | 1  | (sqrt(x^2 + n) - x) / 2                   | yes         | no       |
// | 2  | n / (x + sqrt(2 n))                       | yes         | no       |
// | 3  | n cos(pi/6 + x/n) + n,   x < 5 pi n / 6   | yes         | 5 pi n/6 |
// | 4  | n cos(5 pi/6 + x/n) + n, x < pi n / 6     | yes         | pi n / 6 |
// | 5  | n (x/n - 1/4)^2,         x < n / 4        | yes         | n / 4    |
// | 6  | n - x / 2,               x < 2 n          | no (kink)   | 2 n      |
//
// (0 past the threshold.) All have fb'(0) = -1/2, which makes the blend C1
// across f1 = f2; 3, 4 and 5 reach 0 with zero slope (local and C1), 6 with
// slope -1/2 (local, not differentiable there). Function 3 over-blends:
// fb(0) = n (1 + sqrt(3)/2). The thresholds are written with min/max of
// the argument, not with comparisons, so intervals and tuples follow them.
// n = 0 gives plain min/max for every function.

#include <sage/expression/expression.hpp>

namespace sage {

enum class BlendFunction { Sqrt = 1, Rational = 2, CosOver = 3, Cos = 4, Quadratic = 5, Linear = 6 };

/// Blend function 1..6 from its number in paper 000; throws
/// std::invalid_argument for other numbers.
BlendFunction blend_function_from_number(int number);

/// fb(x, n) as an expression of x >= 0. Throws std::invalid_argument for
/// a negative or non-finite amount.
Expr blend_amount(const Expr& x, BlendFunction fb, double n);
/// x where fb reaches 0 for good (infinity for the non-local 1 and 2).
double blend_threshold(BlendFunction fb, double n);

Expr blend_union(const Expr& f1, const Expr& f2, BlendFunction fb, double n);
Expr blend_intersection(const Expr& f1, const Expr& f2, BlendFunction fb, double n);
Expr blend_difference(const Expr& f1, const Expr& f2, BlendFunction fb, double n);

}  // namespace sage
