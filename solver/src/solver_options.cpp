#include <sage/solver/solver_options.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

// The options' defaults and parsers, shared by every physics.

namespace sage::solver {

// The second function absorbs the Robin defect within the band, so P needs
// no layer, and V D1(P) costs O(band^1.5 h^(n-1)) in H1: below h^n for
// band ~ h^(2/3). A band of a few cells (~ h) would do as well in exact
// arithmetic, but its cut-offs would then vary within a cell at every h,
// and Gauss rules would leave a relative error that does not fall with h
// (README, Robin structure; bench/robin_structure_study).
double robin_band_width(double fraction, double cell_width, double longest_side) {
  if (fraction <= 0.0) return 0.0;
  return fraction * longest_side * std::pow(cell_width / longest_side, 2.0 / 3.0);
}

double nitsche_penalty(double requested, int degree) {
  return requested > 0.0 ? requested : kNitschePenaltyFactor * (degree + 1) * (degree + 1);
}

DirichletRoute parse_dirichlet_route(const std::string& text) {
  if (text == "auto") return DirichletRoute::Automatic;
  if (text == "weak") return DirichletRoute::Weak;
  if (text == "structure") return DirichletRoute::Structure;
  throw std::invalid_argument("expected auto, weak or structure, not '" + text + "'");
}

double automatic_cg_tolerance(double cell_width, double longest_side, int degree) {
  const double tolerance = std::pow(cell_width / longest_side, degree + 3);
  return std::min(std::max(tolerance, 1e-12), 1e-6);
}

}  // namespace sage::solver
