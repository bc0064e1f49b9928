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

bool is_weak(const BoundarySplit::Part& part) { return !part.value; }

}  // namespace

BoundaryStructure boundary_structure(const BoundarySplit& split, const std::array<double, 3>& interior,
                                     bool dirichlet_structure) {
  BoundaryStructure s;
  for (const BoundarySplit::Part& part : split.parts) {
    Tape tape(part.selector, split.dimension);
    Evaluator<double> eval(tape);
    const double sign = eval.at(interior);
    if (!(sign != 0.0) || !std::isfinite(sign))
      throw std::invalid_argument("boundary part '" + part.name +
                                  "': its field vanishes inside the domain, so it cannot name a part of the boundary");
    s.selectors.push_back(sign > 0 ? part.selector : -part.selector);
    s.has_weak_parts = s.has_weak_parts || is_weak(part);
  }
  const bool rest_weak = is_weak(split.rest);
  s.has_weak_parts = s.has_weak_parts || rest_weak;

  std::vector<Expr> dirichlet_fields, dirichlet_values;
  for (std::size_t k = 0; k < split.parts.size(); ++k) {
    if (is_weak(split.parts[k])) continue;
    dirichlet_fields.push_back(s.selectors[k]);
    dirichlet_values.push_back(*split.parts[k].value);
  }
  bool has_robin = split.rest.robin;
  for (const BoundarySplit::Part& part : split.parts) has_robin = has_robin || part.robin;
  // No condition given for the rest beside weak and Dirichlet parts: the
  // named parts claim the boundary, and omega_D is theirs alone.
  s.rest_must_be_empty =
      dirichlet_structure && !split.rest_given && s.has_weak_parts && !dirichlet_fields.empty() && !rest_weak;

  if (!dirichlet_structure) {
    s.pure_neumann = rest_weak && dirichlet_fields.empty() && !has_robin;
    s.dirichlet_weight = 1.0;
    s.dirichlet_extension = 0.0;
  } else if (!rest_weak && !s.rest_must_be_empty) {
    if (s.has_weak_parts)
      throw std::invalid_argument(
          std::string("with parts of weak conditions (Neumann, Robin, traction) the default boundary condition must "
                      "not be Dirichlet (a prescribed value)") +
          (split.rest_given ? "" : " (without a \"default\", the boundary no named part claims is Dirichlet u = 0)") +
          ": name the parts of prescribed values and give the default the weak condition");
    s.dirichlet_weight = split.field;
    bool uniform = true;
    for (const Expr& value : dirichlet_values) uniform = uniform && same_expression(value, *split.rest.value);
    // Data given piece by piece: interpolate between the named pieces.
    s.dirichlet_extension = uniform || dirichlet_values.empty()
                                ? *split.rest.value
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
  if (dirichlet_structure && split.extension) s.dirichlet_extension = *split.extension;
  return s;
}

}  // namespace sage::solver
