#include "data_check.hpp"

#include "message_text.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

namespace sage::solver {

DataError::DataError(std::string datum, double value, const std::optional<std::array<double, 3>>& point, int dimension,
                     const std::string& requirement)
    : std::invalid_argument([&] {
        std::string where = " everywhere";
        if (point) {
          where = " at (";
          for (int a = 0; a < dimension; ++a)
            where += (a ? ", " : "") + number_text((*point)[static_cast<std::size_t>(a)], 6);
          where += ")";
        }
        return datum + " is " + number_text(value, 6) + where + ": " + requirement;
      }()),
      datum_(std::move(datum)),
      value_(value),
      point_(point) {}

std::string pointer_token(const std::string& name) {
  std::string token;
  for (char c : name) {
    if (c == '~') {
      token += "~0";
    } else if (c == '/') {
      token += "~1";
    } else {
      token += c;
    }
  }
  return token;
}

namespace {

constexpr const char* kAxisName[3] = {"x", "y", "z"};

/// Why `value` breaks its rule, or "" when it does not. `robin_scale`:
/// h / k at the point, for a Robin coefficient.
std::string breach(DataNeed need, double value, double robin_scale) {
  if (!std::isfinite(value))
    return "every datum must be finite wherever the solver reads it (the domain for volume data, its part of the "
           "boundary for boundary data)";
  if (std::abs(value) > kLargestDatum)
    return "a datum's magnitude must stay below " + number_text(kLargestDatum, 6) +
           " (beyond it, the assembly's products overflow double precision): change the units";
  switch (need) {
    case DataNeed::Positive:
      if (!(value >= kSmallestModulus))
        return "the conductivity must be positive everywhere in the domain (where k <= 0, -div(k grad u) = f is "
               "not elliptic and the system has no positive definite matrix; below " +
               number_text(kSmallestModulus, 6) + " the stiffness underflows)";
      break;
    case DataNeed::RobinCoefficient:
      if (value < 0.0)
        return "a Robin coefficient must not be negative (with beta < 0 the problem is not coercive: its solution "
               "need not exist or be unique)";
      if (value * robin_scale > kLargestBiotNumber)
        return "beta h / k is " + number_text(value * robin_scale, 6) + " here, above " +
               number_text(kLargestBiotNumber, 6) +
               ": the Robin condition is u = flux / beta to rounding and the system is singular in double "
               "precision (give a Dirichlet condition instead)";
      break;
    case DataNeed::Finite: break;
  }
  return "";
}

std::string part_pointer(const std::string& name) { return "/boundary/" + pointer_token(name); }

/// Moves the constant rules out of `rules`, throwing when one fails (a
/// Robin coefficient stays: its limit depends on the conductivity there).
void check_constants(std::vector<DatumRule>& rules, int dimension) {
  std::vector<DatumRule> varying;
  for (DatumRule& rule : rules) {
    if (!rule.formula.is_constant()) {
      varying.push_back(std::move(rule));
      continue;
    }
    const double value = rule.formula.constant_value();
    const std::string why = breach(rule.need, value, 0.0);
    if (!why.empty()) throw DataError(rule.pointer, value, std::nullopt, dimension, why);
    if (rule.need == DataNeed::RobinCoefficient) varying.push_back(std::move(rule));
  }
  rules = std::move(varying);
}

/// The first failure a thread found: the cell, the rule, the value, the point and why.
struct Failure {
  std::size_t cell = std::numeric_limits<std::size_t>::max();
  const DatumRule* rule = nullptr;
  double value = 0.0;
  std::array<double, 3> point{};
  std::string why;
};

/// Checks `rules`, the tape's results from `first` on, at x; records the
/// first failure of cell k. `robin_scale`: h / k at x.
template <int D>
bool check_results(const std::vector<DatumRule>& rules, const Evaluator<double>& eval, std::size_t first, std::size_t k,
                   const std::array<double, D>& x, Failure& failure, double robin_scale = 0.0) {
  for (std::size_t i = 0; i < rules.size(); ++i) {
    const double value = eval.result(first + i);
    std::string why = breach(rules[i].need, value, robin_scale);
    if (why.empty()) continue;
    failure.cell = k;
    failure.rule = &rules[i];
    failure.value = value;
    failure.why = std::move(why);
    for (int a = 0; a < D; ++a) failure.point[static_cast<std::size_t>(a)] = x[static_cast<std::size_t>(a)];
    return false;
  }
  return true;
}

void append_roots(const std::vector<DatumRule>& rules, std::vector<Expr>& roots) {
  for (const DatumRule& rule : rules) roots.push_back(rule.formula);
}

}  // namespace

DataRules poisson_data_rules(const PoissonProblem& problem, bool dirichlet_inside) {
  DataRules rules;
  rules.everywhere.push_back({"/conductivity", problem.conductivity, DataNeed::Positive});
  rules.conductivity = problem.conductivity;
  rules.volume.push_back({"/source", problem.source});
  if (problem.exact) rules.volume.push_back({"/exact", *problem.exact});
  auto part_rules = [&](const BoundaryPart& part, const std::string& name) {
    const std::string at = part_pointer(name);
    std::vector<DatumRule> own;
    switch (part.kind) {
      case BoundaryKind::Dirichlet:
        own.push_back({at + "/value", part.value});
        if (dirichlet_inside) rules.volume.push_back(own.back());
        break;
      case BoundaryKind::Robin:
        own.push_back({at + "/beta", part.beta, DataNeed::RobinCoefficient});
        own.push_back({at + "/flux", part.flux});
        break;
      case BoundaryKind::Neumann: own.push_back({at + "/flux", part.flux}); break;
    }
    rules.parts.push_back(std::move(own));
  };
  for (const BoundaryPart& part : problem.parts) {
    rules.selectors.push_back({part_pointer(part.name) + "/selector", part.selector});
    part_rules(part, part.name);
  }
  part_rules(problem.rest, "default");
  return rules;
}

DataRules elasticity_data_rules(const ElasticityProblem& problem, bool fixed_inside) {
  DataRules rules;
  const int d = problem.domain.dimension;
  for (int c = 0; c < d; ++c) {
    const auto component = static_cast<std::size_t>(c);
    rules.volume.push_back({"/body_force/" + std::to_string(c), problem.body_force[component]});
    if (problem.exact) rules.volume.push_back({"/exact/" + std::to_string(c), (*problem.exact)[component]});
  }
  auto part_rules = [&](const ElasticPart& part, const std::string& name) {
    const std::string at = part_pointer(name);
    std::vector<DatumRule> own;
    for (int c = 0; c < d; ++c) {
      const auto component = static_cast<std::size_t>(c);
      if (part.loaded) own.push_back({at + "/traction/" + std::to_string(c), part.traction[component]});
      if (!part.fixes(c)) continue;
      own.push_back({at + "/displacement/" + kAxisName[c], *part.displacement[component]});
      if (fixed_inside) rules.volume.push_back(own.back());
    }
    if (part.loaded) own.push_back({at + "/pressure", part.pressure});
    rules.parts.push_back(std::move(own));
  };
  for (const ElasticPart& part : problem.parts) {
    rules.selectors.push_back({part_pointer(part.name) + "/selector", part.selector});
    part_rules(part, part.name);
  }
  part_rules(problem.rest, "default");
  return rules;
}

template <int D>
void check_data(const DataRules& given, const CellRules<D>& cells, double cell_width) {
  DataRules rules = given;
  check_constants(rules.volume, D);
  check_constants(rules.everywhere, D);
  for (auto& part : rules.parts) check_constants(part, D);
  // The selectors stay (the surface tape's first results pick the part), constant or not.
  bool varying = !rules.volume.empty() || !rules.everywhere.empty();
  for (const auto& part : rules.parts) varying = varying || !part.empty();
  for (const auto& selector : rules.selectors) varying = varying || !selector.formula.is_constant();
  if (!varying) return;

  // Volume tape: the volume rules, then those read everywhere. Surface
  // tape: the selectors, those read everywhere, then each part's rules.
  std::vector<Expr> volume_roots, surface_roots;
  append_roots(rules.volume, volume_roots);
  append_roots(rules.everywhere, volume_roots);
  append_roots(rules.selectors, surface_roots);
  append_roots(rules.everywhere, surface_roots);
  std::vector<std::size_t> part_first;
  for (const auto& part : rules.parts) {
    part_first.push_back(surface_roots.size());
    append_roots(part, surface_roots);
  }
  const std::size_t conductivity_at = surface_roots.size();
  surface_roots.push_back(rules.conductivity);
  if (volume_roots.empty()) volume_roots.push_back(Expr(0.0));
  const Tape volume_tape(volume_roots, D), surface_tape(surface_roots, D);
  const std::size_t named = rules.selectors.size(), everywhere_first = named;
  const double selector_tolerance = kSelectorTolerance * cell_width;

  Failure first;
#pragma omp parallel
  {
    Evaluator<double> volume_eval(volume_tape), surface_eval(surface_tape);
    Failure own;
    // Static schedule: each thread's cells increase, so its first failure is its earliest.
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < cells.volume.size(); ++k) {
      if (own.rule) continue;
      for (const auto& q : cells.volume[k]) {
        volume_eval.evaluate(q.x.data());
        if (!check_results<D>(rules.volume, volume_eval, 0, k, q.x, own) ||
            !check_results<D>(rules.everywhere, volume_eval, rules.volume.size(), k, q.x, own))
          break;
      }
      if (own.rule || k >= cells.surface.size()) continue;
      for (const auto& s : cells.surface[k]) {
        surface_eval.evaluate(s.x.data());
        if (!check_results<D>(rules.selectors, surface_eval, 0, k, s.x, own) ||
            !check_results<D>(rules.everywhere, surface_eval, everywhere_first, k, s.x, own))
          break;
        const std::size_t part = nearest_part(surface_eval, named, selector_tolerance);
        const double robin_scale = cell_width / surface_eval.result(conductivity_at);
        if (!check_results<D>(rules.parts[part], surface_eval, part_first[part], k, s.x, own, robin_scale)) break;
      }
    }
#pragma omp critical
    if (own.cell < first.cell) first = own;
  }
  if (first.rule) throw DataError(first.rule->pointer, first.value, first.point, D, first.why);
}

template void check_data<2>(const DataRules&, const CellRules<2>&, double);
template void check_data<3>(const DataRules&, const CellRules<3>&, double);

}  // namespace sage::solver
