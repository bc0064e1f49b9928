#include <sage/expression/derivative.hpp>
#include <sage/expression/normalize.hpp>
#include <sage/scalars/rfunction.hpp>
#include <sage/solver/boundary_structure.hpp>
#include <sage/solver/trial_structure.hpp>

#include <stdexcept>

namespace sage::solver {

namespace {

/// The data of several parts as one field: the common expression, or
/// transfinite interpolation between the parts.
Expr blended(const std::vector<Expr>& fields, const std::vector<Expr>& data) {
  bool uniform = true;
  for (const Expr& d : data) uniform = uniform && same_expression(d, data[0]);
  return uniform ? data[0] : transfinite_interpolation(fields, data);
}

}  // namespace

RobinRoute parse_robin_route(const std::string& text) {
  if (text == "weak") return RobinRoute::Weak;
  if (text == "structure") return RobinRoute::Structure;
  throw std::invalid_argument("expected weak or structure, not '" + text + "'");
}

TrialStructure dirichlet_trial(const BoundaryStructure& structure) {
  TrialStructure t;
  t.scale = structure.dirichlet_weight;
  t.offset = structure.dirichlet_extension;
  t.robin_weight = 0.0;
  t.robin_field = 0.0;
  return t;
}

Expr localized_weight(const Expr& w, const Expr& distance, double band, int power) {
  if (band <= 0.0) return w;
  return w * pow_int(clamp_nonneg(1.0 - distance / band), power);
}

TrialStructure robin_trial(const PoissonProblem& problem, const BoundaryStructure& structure, double band, int power) {
  if (band > 0.0 && power < 2)
    throw std::invalid_argument("the Robin structure's cut-off needs power >= 2 (C^1 weight)");
  if (!structure.has_weak_parts) throw std::invalid_argument("the Robin structure needs a Neumann or Robin part");
  const int d = problem.domain.dimension;
  std::vector<Expr> fields, betas, fluxes;
  bool has_dirichlet = false;
  for (std::size_t k = 0; k < problem.parts.size(); ++k) {
    const BoundaryPart& part = problem.parts[k];
    if (part.kind == BoundaryKind::Dirichlet) {
      has_dirichlet = true;
      continue;
    }
    fields.push_back(normalize(structure.selectors[k], d));
    betas.push_back(part.beta);
    fluxes.push_back(part.flux);
  }
  TrialStructure t;
  Expr beta, flux;
  if (fields.empty()) {
    if (has_dirichlet)
      throw std::invalid_argument(
          "Robin structure: with Dirichlet parts, name the Neumann and Robin parts (the structure is built on their "
          "fields), or use the weak route");
    t.robin_field = normalize(problem.domain.field, d);
    t.robin_weight = t.robin_field;
    beta = problem.rest.beta;
    flux = problem.rest.flux;
  } else {
    Expr field = fields[0];
    for (std::size_t k = 1; k < fields.size(); ++k) field = r_and(field, fields[k], RSystem::r0());
    t.robin_field = field;
    t.joined_with_dirichlet = has_dirichlet;
    // W = omega_R chi with chi = omega_D^2 / (omega_D^2 + omega_R^2): chi = 1 on the structured parts
    // (so W is normalized there), and W vanishes to second order on the Dirichlet parts, so it
    // leaves du/dn free there (a first-order zero would impose a Robin condition on them too).
    const Expr omega_d2 = square(structure.dirichlet_weight);
    t.robin_weight = has_dirichlet ? field * div_safe(omega_d2, omega_d2 + square(field)) : field;
    beta = blended(fields, betas);
    flux = blended(fields, fluxes);
  }
  // D1 follows the global W (smooth, normalized on the parts); the multiplier of the structure is
  // W cut off at distance band (localized_weight), so that W times the second derivatives of the
  // splines in grad u is O(band) instead of O(1). The condition still holds exactly: on the parts
  // the cut W vanishes and D1(cut W) = |grad W|^2 psi'(0) = 1. The cut is by omega_R, the distance
  // to the structured parts (by W, which vanishes on the Dirichlet parts too, V would reach along
  // those as well). The second function's multiplier is V omega_R: a second-order zero on the
  // structured parts, and V times the Robin defect of the solution is V omega_R times a smooth
  // function.
  const Expr global = t.robin_weight;
  t.robin_weight = localized_weight(global, t.robin_field, band, power);
  if (band > 0.0) t.second_weight = t.robin_weight * t.robin_field;
  const Expr& w = t.robin_weight;
  const Expr& omega_d = structure.dirichlet_weight;
  const Expr& g = structure.dirichlet_extension;
  const std::vector<Expr> grad_w = gradient(global, d);
  auto d1 = [&](const Expr& f) {
    Expr s = 0.0;
    for (int a = 0; a < d; ++a) s = s + grad_w[static_cast<std::size_t>(a)] * derivative(f, a);
    return s;
  };
  const Expr robin_factor = 1.0 + w * beta / problem.conductivity;
  t.scale = omega_d * robin_factor - w * d1(omega_d);
  for (int a = 0; a < d; ++a) t.transport.push_back(w * omega_d * grad_w[static_cast<std::size_t>(a)]);
  t.offset = g * robin_factor - w * d1(g) - w * flux / problem.conductivity;
  return t;
}

}  // namespace sage::solver
