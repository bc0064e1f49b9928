#include "tape_specializer_state.hpp"

#include <sage/tape/evaluator.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>

namespace sage {

using namespace specialization;

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
