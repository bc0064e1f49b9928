#include "partial_bounds.hpp"
#include "tape_specializer_state.hpp"

#include <sage/tape/evaluator.hpp>
#include <sage/tape/far_field.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>

namespace sage {

using namespace specialization;

namespace {

// Where the roots barely depend on a subtree (a far edge beside a near one
// under R0: d/dy (x + y - sqrt(x^2 + y^2)) = 1 - y / r, about x^2 / 2y^2),
// its patch may leave a tail up to tolerance / sensitivity, but at most
// 1e4 times the tolerance: the bounds are first order, over the exact
// values' enclosures.
constexpr double kLeastSensitivity = 1e-4;

using Jet = Tuple<3, 1>;  // value and gradient at a box's centre

// First-order distance from the centre to the zero set of t: |t| / |grad t|.
double zero_distance(const Jet& t) {
  const auto g = t.gradient();
  const double norm = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  const double d = std::abs(t.value()) / norm;
  return std::isnan(d) ? 0.0 : d;
}

// First-order distance from the centre to the corner of an R-function,
// where both arguments vanish: the shortest step d with a + grad a . d = 0
// and b + grad b . d = 0, |d|^2 = v^T (J J^T)^-1 v for v = (a, b) and J the
// rows grad a, grad b. At least max(zero_distance(a), zero_distance(b)),
// and much more where the zero sets pass close by but cross far away (edge
// lines of a coast running side by side), or never (parallel).
double corner_distance(const Jet& a, const Jet& b) {
  const auto ga = a.gradient(), gb = b.gradient();
  double aa = 0, ab = 0, bb = 0;
  for (int k = 0; k < 3; ++k) {
    aa += ga[k] * ga[k];
    ab += ga[k] * gb[k];
    bb += gb[k] * gb[k];
  }
  const double va = a.value(), vb = b.value();
  const double det = aa * bb - ab * ab;
  // Parallel (or vanishing) gradients: the zero sets do not cross to first
  // order, so the larger distance to one of them bounds the corner's.
  if (!(det > 1e-12 * aa * bb)) return std::max(zero_distance(a), zero_distance(b));
  const double q = (bb * va * va - 2 * ab * va * vb + aa * vb * vb) / det;
  return std::isnan(q) ? 0.0 : std::sqrt(std::max(q, 0.0));
}

// |grad c|^2 summed over the terms when a kept instruction's value is a sum
// of squares c^2 (an even power b^2m is (b^m)^2), else -1.
double squares_gradient2(const Instruction& ins, const Jet& a, const double* argument_squares_gradient2) {
  auto norm2 = [](const Jet& t) {
    const auto g = t.gradient();
    return g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
  };
  switch (ins.op) {
    case Op::Square: return norm2(a);
    case Op::PowInt: {
      const int p = static_cast<int>(ins.p0);
      if (p <= 0 || p % 2 != 0) return -1;
      const double m = p / 2, c = std::pow(a.value(), m - 1);  // d b^m = m b^(m-1) grad b
      return m * m * c * c * norm2(a);
    }
    case Op::Add:
      if (argument_squares_gradient2[0] < 0 || argument_squares_gradient2[1] < 0) return -1;
      return argument_squares_gradient2[0] + argument_squares_gradient2[1];
    default: return -1;
  }
}

// Whether a kept instruction is analytic across the enlarged box, judged
// from its arguments at the centre: every singular set (a root, a kink, the
// corner of an R-function where both arguments vanish) must be farther
// than `reach` by the first-order distance estimate. Interval enclosures
// of deep R-function trees are too wide to show this; the estimate is not a
// proof, and the fitted patch's coefficients are checked anyway.
bool analytic_near(const Instruction& ins, const Jet& a, const Jet& b, const Jet& out, double reach,
                   double a_squares_gradient2) {
  if (std::isnan(out.value())) return false;
  switch (ins.op) {
    case Op::Sqrt:
      // The root of a sum of squares c1^2 + c2^2 branches where c1 = +-i c2,
      // at the first-order distance sqrt(c1^2 + c2^2) / sqrt(|grad c1|^2 +
      // |grad c2|^2): those complex zeros bound a patch's convergence. A
      // far edge's trimmed field (t^2 + h^4 / L^2, then h^2 + q^2) has them
      // twice as far as the sum's first-order zero |a| / |grad a|.
      if (a_squares_gradient2 >= 0) return a.value() > 0 && std::sqrt(a.value() / a_squares_gradient2) > reach;
      [[fallthrough]];
    case Op::Log:
    case Op::PowReal: return a.value() > 0 && zero_distance(a) > reach;
    case Op::Abs:
    case Op::Step: return zero_distance(a) > reach;
    case Op::Div:
    case Op::DivSafe: return zero_distance(b) > reach;
    case Op::PowInt: return ins.p0 >= 0 || zero_distance(a) > reach;
    case Op::Min:
    case Op::Max: return zero_distance(a - b) > reach;
    case Op::Classify: return false;  // unless settled over the box (not kept)
    case Op::RAnd:
    case Op::ROr: {
      const RSystem s{static_cast<RKind>(static_cast<int>(ins.p0)), ins.p1};
      // min/max (and R_alpha at alpha = 1) kink where the arguments meet;
      // the others are singular only where both vanish.
      if (s.kind == RKind::MinMax || (s.kind == RKind::RAlpha && s.parameter >= 1.0))
        return zero_distance(a - b) > reach;
      // Far from either zero set, or from where they cross. The crossing
      // is extrapolated from the centre, so it must be twice as far: at
      // once as far, patches that passed their tail test deviated more
      // (Lake Vanern with rp:4 on 1000^2 points: 9.2e-10 of the diagonal
      // against 2.7e-10).
      return std::max(zero_distance(a), zero_distance(b)) > reach || corner_distance(a, b) > 2 * reach;
    }
    default: return true;
  }
}

}  // namespace

bool far_field_pays(const Tape& tape) {
  if (tape.dimension() != 2) return false;
  for (const Instruction& ins : tape.code())
    if ((ins.op == Op::RAnd || ins.op == Op::ROr) && static_cast<int>(ins.p0) != static_cast<int>(RKind::MinMax))
      return true;
  return false;
}

void TapeSpecializer::mark_analytic(const Interval* box, double enlargement) {
  const auto& code = tape_->code();
  const int dimension = tape_->dimension();
  double half_diagonal2 = 0;
  std::array<double, 3> centre{0, 0, 0};
  for (int a = 0; a < dimension; ++a) {
    centre[a] = box[a].mid();
    half_diagonal2 += 0.25 * box[a].width() * box[a].width();
  }
  const double reach = enlargement * std::sqrt(half_diagonal2);
  jets_.resize(tape_->register_count());
  for (const auto& [r, c] : tape_->constants()) jets_[r] = Jet(c);
  for (int a = 0; a < dimension; ++a) jets_[static_cast<std::size_t>(a)] = Jet::variable(a, centre[a]);
  analytic_.assign(code.size(), 0);
  register_analytic_.assign(tape_->register_count(), 1);  // variables and constants
  const auto& producers = tape_->producers();
  squares_gradient2_.assign(code.size(), -1);
  auto squares_of = [&](std::uint32_t producer) {
    return producer == kNoProducer ? -1.0 : squares_gradient2_[producer];
  };
  for (std::size_t i = 0; i < code.size(); ++i) {
    const Instruction& ins = code[i];
    const Jet out = evaluate_instruction<Jet>(ins, jets_.data());
    const int k = arity(ins.op);
    bool analytic = true;
    switch (fate_[i]) {
      case Fate::FirstArgument: analytic = register_analytic_[ins.a]; break;  // as analytic as what it forwards
      case Fate::SecondArgument: analytic = register_analytic_[ins.b]; break;
      case Fate::Constant: break;
      default: {
        const double arguments[2] = {squares_of(producers[i][0]), squares_of(producers[i][1])};
        squares_gradient2_[i] = squares_gradient2(ins, jets_[ins.a], arguments);
        analytic = (k < 1 || register_analytic_[ins.a]) && (k < 2 || register_analytic_[ins.b]) &&
                   analytic_near(ins, jets_[ins.a], jets_[ins.b], out, reach, arguments[0]);
      }
    }
    analytic_[i] = analytic;
    register_analytic_[ins.out] = analytic;
    jets_[ins.out] = out;
  }
}

std::optional<Tape> TapeSpecializer::approximate(const Interval* box, const Approximation& settings) {
  std::array<Interval, 3> enlarged{Interval(0.0), Interval(0.0), Interval(0.0)};
  for (int a = 0; a < tape_->dimension(); ++a) {
    const double half = 0.5 * box[a].width() * settings.enlargement;
    enlarged[a] = Interval(box[a].mid() - half, box[a].mid() + half);
  }
  bool changed = decide(enlarged.data());
  mark_analytic(box, settings.enlargement);
  changed |= fit_patches(box, settings);
  if (!changed) return std::nullopt;
  return rebuild();
}

bool TapeSpecializer::fit_patches(const Interval* box, const Approximation& settings) {
  const auto& code = tape_->code();
  const std::size_t n = code.size();
  const int dimension = tape_->dimension();

  // The size of each subtree as the specialized program would run it, and
  // whether an analytic instruction reads it (then it is not the largest),
  // from the producers of the arguments.
  const auto& producers = tape_->producers();
  Scratch& w = *scratch_;
  std::vector<std::size_t>& size = w.size;
  std::vector<char>& read_by_analytic = w.read_by_analytic;
  std::vector<std::array<std::uint32_t, 2>>& read = w.read;
  size.assign(n, 0);
  read_by_analytic.assign(n, 0);
  read.resize(n);
  auto size_of = [&](std::uint32_t j) { return j == kNoProducer ? std::size_t{0} : size[j]; };
  for (std::size_t i = 0; i < n; ++i) {
    const Instruction& ins = code[i];
    // Only the arguments the specialized program reads.
    const std::uint32_t a =
        fate_[i] != Fate::SecondArgument && fate_[i] != Fate::Constant ? producers[i][0] : kNoProducer;
    const std::uint32_t b =
        fate_[i] != Fate::FirstArgument && fate_[i] != Fate::Constant && ins.b != ins.a ? producers[i][1] : kNoProducer;
    read[i] = {a, b};
    size[i] = (fate_[i] == Fate::Keep ? 1 : 0) + size_of(a) + size_of(b);
    if (analytic_[i]) {
      if (a != kNoProducer) read_by_analytic[a] = 1;
      if (b != kNoProducer) read_by_analytic[b] = 1;
    }
  }
  // Every analytic subtree large enough is sampled; the largest are fitted
  // first, and where a fit fails (the first-order estimate missed a
  // singularity, or the series converges too slowly) its subtrees are
  // tried instead.
  std::vector<std::size_t>&sampled = w.sampled, &row = w.row, &pending = w.pending;
  sampled.clear();
  pending.clear();
  row.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    if (analytic_[i] && size[i] >= settings.min_subtree) {
      row[i] = sampled.size();
      sampled.push_back(i);
      if (!read_by_analytic[i]) pending.push_back(i);
    }
  if (pending.empty()) return false;
  const std::vector<double>& sensitivity = sensitivities();

  // Their values at the samples: the program that computes them (what they
  // read, with this box's fates), run at all samples in one batch.
  const Tape sampler = rebuild(&sampled);
  const int degree = settings.sampling_degree;
  std::size_t samples = 1;
  for (int a = 0; a < dimension; ++a) samples *= static_cast<std::size_t>(degree + 1);
  // The samples are a tensor grid: rows of m = degree + 1 points in x.
  const std::size_t m = static_cast<std::size_t>(degree + 1);
  std::vector<double>& xs = w.xs;
  std::vector<std::array<double, 2>>& rows = w.rows;
  xs.resize(m);
  rows.resize(samples / m);
  for (std::size_t i = 0; i < m; ++i) xs[i] = ChebyshevPatch::sample_point(box, dimension, degree, i)[0];
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::array<double, 3> p = ChebyshevPatch::sample_point(box, dimension, degree, r * m);
    rows[r] = {p[1], p[2]};
  }
  if (w.batch)
    w.batch->rebind(sampler, samples);
  else
    w.batch = std::make_unique<BatchEvaluator<double>>(sampler, samples);
  BatchEvaluator<double>& batch = *w.batch;
  batch.evaluate_rows(xs.data(), m, rows.data(), rows.size());

  bool made = false;
  patch_.resize(n);
  std::vector<double>& values = w.values;
  values.resize(samples);
  while (!pending.empty()) {
    const std::size_t i = pending.back();
    pending.pop_back();
    // The patch's error reaches the roots scaled by at most sensitivity[i]:
    // each patch may move them by the tolerance.
    const double tolerance = settings.tolerance / std::max(kLeastSensitivity, sensitivity[i]);
    if (tolerance > 0) {
      for (std::size_t s = 0; s < samples; ++s) values[s] = batch.result(s, row[i]);
      if (auto patch = ChebyshevPatch::fit(box, dimension, degree, values, tolerance)) {
        fate_[i] = Fate::Patch;
        patch_[i] = std::move(patch);
        made = true;
        continue;
      }
    }
    for (std::uint32_t child : read[i])
      if (child != kNoProducer && analytic_[child] && size[child] >= settings.min_subtree) pending.push_back(child);
  }
  return made;
}

const std::vector<double>& TapeSpecializer::sensitivities() {
  const auto& code = tape_->code();
  const auto& producers = tape_->producers();
  std::vector<double>& sensitivity = scratch_->sensitivity;
  sensitivity.assign(code.size(), 0.0);
  for (std::uint32_t p : tape_->result_producers())
    if (p != kNoProducer) sensitivity[p] = std::max(sensitivity[p], 1.0);
  // (partial_bound() is never NaN, and a zero partial passes nothing, so no
  // infinity times 0.)
  auto pass = [&](std::uint32_t producer, double s, double partial) {
    if (producer != kNoProducer && partial != 0) sensitivity[producer] += s * partial;
  };
  // Backward: each value's bound is the sum, over what reads it, of the
  // reader's bound times the partial derivative's (the chain rule).
  for (std::size_t i = code.size(); i-- > 0;) {
    const double s = sensitivity[i];
    if (!(s > 0)) continue;
    const Instruction& ins = code[i];
    switch (fate_[i]) {
      case Fate::FirstArgument: pass(producers[i][0], s, 1.0); break;
      case Fate::SecondArgument: pass(producers[i][1], s, 1.0); break;
      case Fate::Keep: {
        const int k = arity(ins.op);
        const Interval a = k >= 1 ? enclosure(producers[i][0], ins.a) : Interval(0.0);
        const Interval b = k >= 2 ? enclosure(producers[i][1], ins.b) : Interval(0.0);
        for (int j = 0; j < k; ++j) pass(producers[i][j], s, detail::partial_bound(ins, a, b, j));
        break;
      }
      case Fate::Constant:
      case Fate::Patch: break;
    }
  }
  return sensitivity;
}

}  // namespace sage
