#pragma once
// Gauss-Legendre rules on [0, 1]: n nodes integrate polynomials of degree
// 2n - 1 exactly. Nodes by Newton's method on the Legendre polynomial,
// accurate to round-off for n <= 32.

#include <vector>

namespace sage::solver {

struct GaussRule {
  std::vector<double> nodes;    // in (0, 1), increasing
  std::vector<double> weights;  // sum to 1
};

/// The n-point rule on [0, 1], 1 <= n <= 32; throws std::invalid_argument otherwise.
const GaussRule& gauss_legendre(int n);

}  // namespace sage::solver
