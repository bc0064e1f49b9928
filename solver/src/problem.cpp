#include <sage/solver/problem.hpp>

namespace sage::solver {

namespace {

BoundarySplit::Part split_part(const BoundaryPart& part) {
  BoundarySplit::Part split{part.name, part.selector};
  if (part.kind == BoundaryKind::Dirichlet) split.value = part.value;
  // A Robin part with beta = 0 is a Neumann part.
  split.robin = part.kind == BoundaryKind::Robin && !(part.beta.is_constant() && part.beta.constant_value() == 0.0);
  return split;
}

}  // namespace

BoundarySplit boundary_split(const PoissonProblem& problem) {
  BoundarySplit split;
  split.dimension = problem.domain.dimension;
  split.field = problem.domain.field;
  for (const BoundaryPart& part : problem.parts) split.parts.push_back(split_part(part));
  split.rest = split_part(problem.rest);
  split.rest_given = problem.rest_given;
  split.extension = problem.dirichlet_extension;
  return split;
}

}  // namespace sage::solver
