#include <sage/solver/boundary_structure.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <cmath>
#include <stdexcept>

namespace sage::solver {

bool same_expression(const Expr& a, const Expr& b) {
  if (a.id() == b.id()) return true;
  return a.is_constant() && b.is_constant() && a.constant_value() == b.constant_value();
}

namespace {

bool is_weak(const BoundaryPart& part) { return part.kind != BoundaryKind::Dirichlet; }

}  // namespace

BoundaryStructure boundary_structure(const PoissonProblem& problem, const std::array<double, 3>& interior,
                                     bool dirichlet_structure) {
  BoundaryStructure s;
  for (const BoundaryPart& part : problem.parts) {
    Tape tape(part.selector, problem.domain.dimension);
    Evaluator<double> eval(tape);
    const double sign = eval.at(interior);
    if (!(sign != 0.0) || !std::isfinite(sign))
      throw std::invalid_argument("boundary part '" + part.name +
                                  "': its field vanishes inside the domain, so it cannot name a part of the boundary");
    s.selectors.push_back(sign > 0 ? part.selector : -part.selector);
    s.has_weak_parts = s.has_weak_parts || is_weak(part);
  }
  const bool rest_weak = is_weak(problem.rest);
  s.has_weak_parts = s.has_weak_parts || rest_weak;

  std::vector<Expr> dirichlet_fields, dirichlet_values;
  for (std::size_t k = 0; k < problem.parts.size(); ++k) {
    if (is_weak(problem.parts[k])) continue;
    dirichlet_fields.push_back(s.selectors[k]);
    dirichlet_values.push_back(problem.parts[k].value);
  }
  // A Robin part with beta = 0 is a Neumann part.
  auto robin = [](const BoundaryPart& part) {
    return part.kind == BoundaryKind::Robin && !(part.beta.is_constant() && part.beta.constant_value() == 0.0);
  };
  bool has_robin = robin(problem.rest);
  for (const BoundaryPart& part : problem.parts) has_robin = has_robin || robin(part);
  // No condition given for the rest beside weak and Dirichlet parts: the
  // named parts claim the boundary, and omega_D is theirs alone.
  s.rest_must_be_empty =
      dirichlet_structure && !problem.rest_given && s.has_weak_parts && !dirichlet_fields.empty() && !rest_weak;

  if (!dirichlet_structure) {
    s.pure_neumann = rest_weak && dirichlet_fields.empty() && !has_robin;
    s.dirichlet_weight = 1.0;
    s.dirichlet_extension = 0.0;
  } else if (!rest_weak && !s.rest_must_be_empty) {
    if (s.has_weak_parts)
      throw std::invalid_argument(
          std::string("with Neumann or Robin parts the default boundary condition must not be Dirichlet") +
          (problem.rest_given ? "" : " (without a \"default\", the boundary no named part claims is Dirichlet u = 0)") +
          ": name the Dirichlet parts and give the default the weak condition");
    s.dirichlet_weight = problem.domain.field;
    bool uniform = true;
    for (const Expr& value : dirichlet_values) uniform = uniform && same_expression(value, problem.rest.value);
    // Data given piece by piece: interpolate between the named pieces.
    s.dirichlet_extension = uniform || dirichlet_values.empty()
                                ? problem.rest.value
                                : transfinite_interpolation(dirichlet_fields, dirichlet_values);
  } else if (dirichlet_fields.empty()) {
    s.pure_neumann = !has_robin;  // the solver checks compatibility and fixes the mean
    s.dirichlet_weight = 1.0;
    s.dirichlet_extension = 0.0;
  } else {
    Expr weight = dirichlet_fields[0];
    for (std::size_t k = 1; k < dirichlet_fields.size(); ++k)
      weight = r_and(weight, dirichlet_fields[k], RSystem::r0());
    s.dirichlet_weight = weight;
    s.dirichlet_extension = transfinite_interpolation(dirichlet_fields, dirichlet_values);
  }
  if (dirichlet_structure && problem.dirichlet_extension) s.dirichlet_extension = *problem.dirichlet_extension;
  return s;
}

}  // namespace sage::solver
