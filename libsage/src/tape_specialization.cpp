#include <sage/batch_evaluator.hpp>
#include <sage/evaluator.hpp>
#include <sage/tape_specialization.hpp>

#include "partial_bounds.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>

namespace sage {

namespace {

bool is_min(const Instruction& ins) {
  return ins.op == Op::Min || (ins.op == Op::RAnd && static_cast<RKind>(static_cast<int>(ins.p0)) == RKind::MinMax);
}
bool is_max(const Instruction& ins) {
  return ins.op == Op::Max || (ins.op == Op::ROr && static_cast<RKind>(static_cast<int>(ins.p0)) == RKind::MinMax);
}

// Where a value of the specialized program comes from: an instruction of
// the original tape (>= 0), or a variable or constant (kVariable - v,
// kConstant - k for entry k of the constant table).
using Source = std::int64_t;
constexpr Source kVariable = -1;   // variable v: kVariable - v (v < 3)
constexpr Source kConstant = -16;  // constant k: kConstant - k
bool is_instruction(Source s) { return s >= 0; }

// Where the roots barely depend on a subtree (a far edge beside a near one
// under R0: d/dy (x + y - sqrt(x^2 + y^2)) = 1 - y / r, about x^2 / 2y^2),
// its patch may leave a tail up to tolerance / sensitivity, but at most
// 1e4 times the tolerance: the bounds are first order, over the exact
// values' enclosures.
constexpr double kLeastSensitivity = 1e-4;

}  // namespace

constexpr std::uint32_t kNoProducer = Tape::kInput;  // a variable or constant

// trace()'s records, for decide_lane() and prune_by_bounds().
struct TapeSpecializer::Bounds {
  std::vector<Interval> out;  // each instruction's enclosure, per box: out[i * lanes + lane]
  std::vector<double> up, low;
  std::vector<std::uint32_t> decisions;    // the mins, maxes, steps and classifiers
  std::vector<std::uint32_t> bound_nodes;  // the mins, maxes and negations
};

struct TapeSpecializer::Scratch {
  std::vector<char> needed, constant_live;
  std::vector<std::uint32_t> root_producers, constant_of_register, reads;
  std::vector<double> constants;
  std::vector<Source> source, arg_a, arg_b, roots;
  std::vector<std::uint32_t> constant_register, reg, free_registers;
  // fit_patches()'s: per instruction, then the sampled subtrees' values
  // (thousands of blocks per thread: allocating and clearing these for each
  // cost more than the fits).
  std::vector<std::size_t> size, row, sampled, pending;
  std::vector<char> read_by_analytic;
  std::vector<std::array<std::uint32_t, 2>> read;
  std::vector<double> xs;  // the samples: xs x rows
  std::vector<std::array<double, 2>> rows;
  std::vector<double> values;
  std::vector<double> sensitivity;
  std::unique_ptr<BatchEvaluator<double>> batch;
};

TapeSpecializer::TapeSpecializer(const Tape& tape)
    : scratch_(std::make_unique<Scratch>()), bounds_(std::make_unique<Bounds>()) {
  rebind(tape);
}
TapeSpecializer::~TapeSpecializer() = default;
TapeSpecializer::TapeSpecializer(TapeSpecializer&&) noexcept = default;
TapeSpecializer& TapeSpecializer::operator=(TapeSpecializer&&) noexcept = default;

void TapeSpecializer::rebind(const Tape& tape) {
  tape_ = &tape;
  fate_.resize(tape.code().size());
  constant_.resize(tape.code().size());
  bounds_->up.resize(tape.code().size());
  bounds_->low.resize(tape.code().size());
}

bool far_field_pays(const Tape& tape) {
  if (tape.dimension() != 2) return false;
  for (const Instruction& ins : tape.code())
    if ((ins.op == Op::RAnd || ins.op == Op::ROr) && static_cast<int>(ins.p0) != static_cast<int>(RKind::MinMax))
      return true;
  return false;
}

bool TapeSpecializer::worthwhile(const Tape& tape) {
  std::size_t prunable = 0;
  for (const Instruction& ins : tape.code())
    prunable += is_min(ins) || is_max(ins) || ins.op == Op::Step || ins.op == Op::Classify;
  return prunable > 0 && 64 * prunable >= tape.code().size();
}

std::optional<Tape> TapeSpecializer::specialize(const Interval* box) {
  if (!decide(box)) return std::nullopt;
  return rebuild();
}

void TapeSpecializer::specialize_each(const std::array<Interval, 3>* boxes, std::size_t count,
                                      std::optional<Tape>* tapes) {
  trace(boxes, count);
  for (std::size_t lane = 0; lane < count; ++lane) {
    tapes[lane].reset();
    if (decide_lane(lane)) tapes[lane] = rebuild();
  }
}

namespace {

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

bool TapeSpecializer::decide(const Interval* box) {
  std::array<Interval, 3> one{Interval(0.0), Interval(0.0), Interval(0.0)};
  std::copy(box, box + tape_->dimension(), one.begin());
  trace(&one, 1);
  return decide_lane(0);
}

// One pass over the code for all boxes: the operation is decoded once per
// instruction, and its enclosures over the boxes are computed together.
void TapeSpecializer::trace(const std::array<Interval, 3>* boxes, std::size_t lanes) {
  const auto& code = tape_->code();
  const int dimension = tape_->dimension();
  Bounds& w = *bounds_;
  lanes_ = lanes;
  registers_.resize(tape_->register_count() * lanes);
  for (const auto& [r, c] : tape_->constants()) std::fill_n(&registers_[r * lanes], lanes, Interval(c));
  for (int v = 0; v < dimension; ++v)
    for (std::size_t l = 0; l < lanes; ++l) registers_[static_cast<std::size_t>(v) * lanes + l] = boxes[l][v];
  w.out.resize(code.size() * lanes);
  w.decisions.clear();
  w.bound_nodes.clear();
  std::array<Interval, 3> variables{};
  for (std::size_t i = 0; i < code.size(); ++i) {
    const Instruction& ins = code[i];
    const Interval* a = &registers_[ins.a * lanes];
    const Interval* b = &registers_[ins.b * lanes];
    Interval* out = &w.out[i * lanes];
    if (ins.op == Op::Classify || ins.op == Op::Patch) {
      for (std::size_t l = 0; l < lanes; ++l) {
        for (int v = 0; v < dimension; ++v) variables[v] = registers_[static_cast<std::size_t>(v) * lanes + l];
        out[l] = ins.op == Op::Classify ? classify_at(*ins.classifier, variables.data())
                                        : ins.patch->evaluate(variables.data());
      }
    } else {
      visit_op(ins.op, [&](auto op) {
        for (std::size_t l = 0; l < lanes; ++l) out[l] = apply_op<decltype(op)::value>(ins, a[l], b[l]);
      });
    }
    std::copy(out, out + lanes, &registers_[ins.out * lanes]);
    const bool min_or_max = is_min(ins) || is_max(ins);
    if (min_or_max || ins.op == Op::Step || ins.op == Op::Classify)
      w.decisions.push_back(static_cast<std::uint32_t>(i));
    if (min_or_max || ins.op == Op::Neg) w.bound_nodes.push_back(static_cast<std::uint32_t>(i));
  }
}

const Interval& TapeSpecializer::enclosure(std::uint32_t producer, std::uint32_t reg) const {
  // Variables and constants keep their registers for the whole pass.
  return producer == kNoProducer ? registers_[reg * lanes_ + lane_] : bounds_->out[producer * lanes_ + lane_];
}

bool TapeSpecializer::decide_lane(std::size_t lane) {
  const auto& code = tape_->code();
  const auto& producers = tape_->producers();
  const Bounds& w = *bounds_;
  lane_ = lane;
  std::fill(fate_.begin(), fate_.end(), Fate::Keep);
  bool pruned = false;
  for (std::uint32_t i : w.decisions) {
    const Instruction& ins = code[i];
    const Interval& out = w.out[i * lanes_ + lane];
    Fate fate = Fate::Keep;
    if (ins.op == Op::Classify) {
      if (out.lo == out.hi) fate = Fate::Constant;
    } else if (ins.op == Op::Step) {
      const Interval& a = enclosure(producers[i][0], ins.a);
      if (a.lo > 0.0 || a.hi < 0.0) fate = Fate::Constant;
    } else {
      const Interval& a = enclosure(producers[i][0], ins.a);
      const Interval& b = enclosure(producers[i][1], ins.b);
      // Strict comparisons: NaN bounds never prune.
      if (is_min(ins)) {
        if (a.hi < b.lo) fate = Fate::FirstArgument;
        if (b.hi < a.lo) fate = Fate::SecondArgument;
      } else {
        if (a.lo > b.hi) fate = Fate::FirstArgument;
        if (b.lo > a.hi) fate = Fate::SecondArgument;
      }
    }
    fate_[i] = fate;
    constant_[i] = out.lo;  // exact for the constant fates: step gives 0 or 1, classify one value
    pruned |= fate != Fate::Keep;
  }
  pruned |= prune_by_bounds();
  return pruned;
}

// Top-down pruning of min/max trees. decide() prunes min(a, b) when one
// argument's enclosure lies below the other's; but in a tree of mins an
// argument is also irrelevant when it lies above any upper bound known
// higher up: in min(min(a, b), c), a is dropped when a.lo > min(b.hi,
// c.hi). Going backward, each instruction read by exactly one min gets
// the bound `up` (values above it cannot be chosen by the mins above, so
// they never reach a root), each read by one max a bound `low` below, and
// negation swaps them. A min whose argument's enclosure lies wholly above
// min(other argument's hi, up) takes the other argument. Only the choices
// of mins change, so results are still bit-identical. Enclosures of
// instructions read more than once (or roots) carry no bound.
bool TapeSpecializer::prune_by_bounds() {
  const auto& code = tape_->code();
  const auto& producers = tape_->producers();
  const auto& readers = tape_->readers();
  Bounds& w = *bounds_;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (std::uint32_t i : w.bound_nodes) {
    w.up[i] = kInf;
    w.low[i] = -kInf;
  }
  auto pass = [&](std::uint32_t producer, double up, double low) {
    if (producer == kNoProducer || readers[producer] != 1) return;
    w.up[producer] = up;
    w.low[producer] = low;
  };
  bool pruned = false;
  for (std::size_t k = w.bound_nodes.size(); k-- > 0;) {
    const std::uint32_t i = w.bound_nodes[k];
    const Instruction& ins = code[i];
    const double up = w.up[i], low = w.low[i];
    const auto [pa, pb] = producers[i];
    if (ins.op == Op::Neg) {
      pass(pa, -low, -up);
      continue;
    }
    const bool min = is_min(ins), max = is_max(ins);
    if (!min && !max) continue;
    const Interval& a = enclosure(pa, ins.a);
    const Interval& b = enclosure(pb, ins.b);
    if (fate_[i] == Fate::Keep) {
      // Strict comparisons: NaN bounds never prune.
      if (min && a.lo > std::min(b.hi, up))
        fate_[i] = Fate::SecondArgument;
      else if (min && b.lo > std::min(a.hi, up))
        fate_[i] = Fate::FirstArgument;
      else if (max && a.hi < std::max(b.lo, low))
        fate_[i] = Fate::SecondArgument;
      else if (max && b.hi < std::max(a.lo, low))
        fate_[i] = Fate::FirstArgument;
      pruned |= fate_[i] != Fate::Keep;
    }
    const bool keep = fate_[i] == Fate::Keep;
    if (fate_[i] != Fate::SecondArgument) {
      if (min)
        pass(pa, keep ? std::min(b.hi, up) : up, -kInf);
      else
        pass(pa, kInf, keep ? std::max(b.lo, low) : low);
    }
    if (fate_[i] != Fate::FirstArgument) {
      if (min)
        pass(pb, keep ? std::min(a.hi, up) : up, -kInf);
      else
        pass(pb, kInf, keep ? std::max(a.lo, low) : low);
    }
  }
  return pruned;
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

Tape TapeSpecializer::rebuild(const std::vector<std::size_t>* outputs) {
  const auto& code = tape_->code();
  const auto& producers = tape_->producers();
  const int dimension = tape_->dimension();
  const std::size_t n = code.size();
  Scratch& w = *scratch_;
  // A patch reads no registers: its subtree dies unless used elsewhere.
  auto arguments = [&](std::size_t i) { return fate_[i] == Fate::Patch ? 0 : arity(code[i].op); };

  // Backward, along the producer links: the instructions whose values the
  // roots need. A dropped instruction forwards the need to the argument it
  // chose, so pruned subtrees are never visited again.
  w.needed.assign(n, 0);
  auto need = [&](std::uint32_t producer) {
    if (producer != kNoProducer) w.needed[producer] = 1;
  };
  std::vector<std::uint32_t>& root_producers = w.root_producers;
  root_producers.clear();
  if (outputs) {
    for (std::size_t i : *outputs) root_producers.push_back(static_cast<std::uint32_t>(i));
  } else {
    root_producers = tape_->result_producers();
  }
  for (std::uint32_t p : root_producers) need(p);
  for (std::size_t i = n; i-- > 0;) {
    if (!w.needed[i]) continue;
    switch (fate_[i]) {
      case Fate::Keep:
        if (arguments(i) >= 1) need(producers[i][0]);
        if (arguments(i) >= 2) need(producers[i][1]);
        break;
      case Fate::FirstArgument: need(producers[i][0]); break;
      case Fate::SecondArgument: need(producers[i][1]); break;
      case Fate::Constant:
      case Fate::Patch: break;
    }
  }

  // Forward over the needed ones: where each value comes from (dropped
  // instructions take their chosen argument's source), and how often the
  // kept instructions and roots read each value.
  w.constants.clear();
  w.constant_of_register.assign(tape_->register_count(), 0);
  for (const auto& [r, c] : tape_->constants()) {
    w.constant_of_register[r] = static_cast<std::uint32_t>(w.constants.size());
    w.constants.push_back(c);
  }
  auto input = [&](std::uint32_t reg) -> Source {  // a variable's or a tape constant's register
    return static_cast<int>(reg) < dimension ? kVariable - static_cast<Source>(reg)
                                             : kConstant - static_cast<Source>(w.constant_of_register[reg]);
  };
  w.source.resize(n);
  w.arg_a.resize(n);
  w.arg_b.resize(n);
  w.reads.assign(n, 0);
  w.constant_live.assign(w.constants.size(), 0);
  auto source_of = [&](std::uint32_t producer, std::uint32_t reg) {
    return producer == kNoProducer ? input(reg) : w.source[producer];
  };
  auto read = [&](Source s, std::uint32_t count) {
    if (is_instruction(s))
      w.reads[static_cast<std::size_t>(s)] += count;
    else if (s <= kConstant)
      w.constant_live[static_cast<std::size_t>(kConstant - s)] = 1;
  };
  std::size_t live_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!w.needed[i]) continue;
    const Instruction& ins = code[i];
    switch (fate_[i]) {
      case Fate::Keep:
      case Fate::Patch: {
        w.source[i] = static_cast<Source>(i);
        ++live_count;
        const int k = arguments(i);
        if (k >= 1) read(w.arg_a[i] = source_of(producers[i][0], ins.a), 1);
        if (k >= 2) read(w.arg_b[i] = source_of(producers[i][1], ins.b), 1);
        break;
      }
      case Fate::FirstArgument: w.source[i] = source_of(producers[i][0], ins.a); break;
      case Fate::SecondArgument: w.source[i] = source_of(producers[i][1], ins.b); break;
      case Fate::Constant:
        w.source[i] = kConstant - static_cast<Source>(w.constants.size());
        w.constants.push_back(constant_[i]);
        w.constant_live.push_back(0);
        break;
    }
  }
  w.roots.clear();
  for (std::size_t k = 0; k < root_producers.size(); ++k) {
    const Source s = root_producers[k] == kNoProducer ? input(tape_->results()[k]) : w.source[root_producers[k]];
    w.roots.push_back(s);
    read(s, 2);  // read forever: never freed
  }

  // Emit: variables in their fixed registers, live constants next, then the
  // live instructions with registers reused after their last read.
  Tape t;
  t.dimension_ = dimension;
  t.classifiers_ = tape_->classifiers_;
  t.registers_ = static_cast<std::size_t>(dimension);
  w.constant_register.resize(w.constants.size());
  for (std::size_t k = 0; k < w.constants.size(); ++k) {
    if (!w.constant_live[k]) continue;
    w.constant_register[k] = static_cast<std::uint32_t>(t.registers_++);  // never reused
    t.constants_.emplace_back(w.constant_register[k], w.constants[k]);
  }
  w.reg.resize(n);
  auto register_of = [&](Source s) -> std::uint32_t {
    if (is_instruction(s)) return w.reg[static_cast<std::size_t>(s)];
    if (s <= kConstant) return w.constant_register[static_cast<std::size_t>(kConstant - s)];
    return Tape::variable_register(static_cast<int>(kVariable - s));
  };
  // Frees the register of an instruction's value at its last read.
  auto release = [&](Source s) {
    if (is_instruction(s) && --w.reads[static_cast<std::size_t>(s)] == 0)
      w.free_registers.push_back(w.reg[static_cast<std::size_t>(s)]);
  };
  w.free_registers.clear();
  t.code_.reserve(live_count);
  for (std::size_t i = 0; i < n; ++i) {
    if (!w.needed[i] || (fate_[i] != Fate::Keep && fate_[i] != Fate::Patch)) continue;
    Instruction ins = code[i];
    if (fate_[i] == Fate::Patch) {
      ins.op = Op::Patch;
      ins.patch = patch_[i].get();
      ins.classifier = nullptr;
      t.patches_.push_back(patch_[i]);
    } else if (ins.op == Op::Patch) {
      t.patches_.push_back(ins.patch->shared_from_this());
    }
    const int k = arguments(i);
    if (k >= 1) ins.a = register_of(w.arg_a[i]);
    if (k >= 2) ins.b = register_of(w.arg_b[i]);
    // The output may reuse an argument's register, as in Tape's compiler.
    if (k >= 1) release(w.arg_a[i]);
    if (k >= 2) release(w.arg_b[i]);
    if (!w.free_registers.empty()) {
      ins.out = w.free_registers.back();
      w.free_registers.pop_back();
    } else {
      ins.out = static_cast<std::uint32_t>(t.registers_++);
    }
    w.reg[i] = ins.out;
    t.code_.push_back(ins);
  }
  for (Source r : w.roots) t.results_.push_back(register_of(r));
  t.link();
  return t;
}

}  // namespace sage
