#include <sage/solver/gauss.hpp>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sage::solver {

namespace {

GaussRule compute_rule(int n) {
  GaussRule rule;
  rule.nodes.resize(static_cast<std::size_t>(n));
  rule.weights.resize(static_cast<std::size_t>(n));
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(pi * (i + 0.75) / (n + 0.5));  // Tricomi's first guess, descending
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x;  // Legendre recurrence for P_n(x) and P_{n-1}(x)
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    const double weight = 2.0 / ((1.0 - x * x) * derivative * derivative);
    // Map [-1, 1] to [0, 1], ascending.
    rule.nodes[static_cast<std::size_t>(n - 1 - i)] = 0.5 * (x + 1.0);
    rule.weights[static_cast<std::size_t>(n - 1 - i)] = 0.5 * weight;
  }
  return rule;
}

}  // namespace

const GaussRule& gauss_legendre(int n) {
  if (n < 1 || n > 32) throw std::invalid_argument("Gauss rule needs 1..32 nodes, not " + std::to_string(n));
  static const std::array<GaussRule, 33> rules = [] {
    std::array<GaussRule, 33> all;
    for (int k = 1; k <= 32; ++k) all[static_cast<std::size_t>(k)] = compute_rule(k);
    return all;
  }();
  return rules[static_cast<std::size_t>(n)];
}

}  // namespace sage::solver
