#include <sage/evaluator.hpp>
#include <sage/tape_specialization.hpp>

#include <algorithm>
#include <cstdint>

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

}  // namespace

TapeSpecializer::TapeSpecializer(const Tape& tape)
    : tape_(&tape), registers_(tape.register_count()), fate_(tape.code().size()), constant_(tape.code().size()) {
  for (const auto& [r, c] : tape.constants()) registers_[r] = Interval(c);
}

bool TapeSpecializer::worthwhile(const Tape& tape) {
  std::size_t prunable = 0;
  for (const Instruction& ins : tape.code())
    prunable += is_min(ins) || is_max(ins) || ins.op == Op::Step || ins.op == Op::Classify;
  return prunable > 0 && 64 * prunable >= tape.code().size();
}

std::optional<Tape> TapeSpecializer::specialize(const Interval* box) {
  for (int i = 0; i < tape_->dimension(); ++i) registers_[i] = box[i];
  bool pruned = false;
  const auto& code = tape_->code();
  for (std::size_t i = 0; i < code.size(); ++i) {
    const Instruction& ins = code[i];
    Fate fate = Fate::Keep;
    Interval out;
    if (ins.op == Op::Classify) {
      out = classify_at(*ins.classifier, registers_.data());
      if (out.lo == out.hi) fate = Fate::Constant;
    } else {
      const Interval& a = registers_[ins.a];
      const Interval& b = registers_[ins.b];
      // Strict comparisons: NaN bounds never prune.
      if (is_min(ins)) {
        if (a.hi < b.lo) fate = Fate::FirstArgument;
        if (b.hi < a.lo) fate = Fate::SecondArgument;
      } else if (is_max(ins)) {
        if (a.lo > b.hi) fate = Fate::FirstArgument;
        if (b.lo > a.hi) fate = Fate::SecondArgument;
      }
      out = apply<Interval>(ins, a, b);
      if (ins.op == Op::Step && (a.lo > 0.0 || a.hi < 0.0)) fate = Fate::Constant;
    }
    fate_[i] = fate;
    constant_[i] = out.lo;  // exact for the constant fates: step gives 0 or 1, classify one value
    pruned |= fate != Fate::Keep;
    registers_[ins.out] = out;
  }
  if (!pruned) return std::nullopt;
  return rebuild();
}

Tape TapeSpecializer::rebuild() const {
  const auto& code = tape_->code();
  const int dimension = tape_->dimension();
  const std::size_t n = code.size();

  // Forward: the source of every register as the code runs, with dropped
  // instructions forwarding their chosen argument.
  std::vector<Source> source_of_register(tape_->register_count(), 0);
  std::vector<double> constants;
  for (int v = 0; v < dimension; ++v) source_of_register[v] = kVariable - v;
  for (const auto& [r, c] : tape_->constants()) {
    source_of_register[r] = kConstant - static_cast<Source>(constants.size());
    constants.push_back(c);
  }
  std::vector<Source> arg_a(n), arg_b(n), result(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Instruction& ins = code[i];
    arg_a[i] = source_of_register[ins.a];
    arg_b[i] = source_of_register[ins.b];
    switch (fate_[i]) {
      case Fate::Keep: result[i] = static_cast<Source>(i); break;
      case Fate::FirstArgument: result[i] = arg_a[i]; break;
      case Fate::SecondArgument: result[i] = arg_b[i]; break;
      case Fate::Constant:
        result[i] = kConstant - static_cast<Source>(constants.size());
        constants.push_back(constant_[i]);
        break;
    }
    source_of_register[ins.out] = result[i];
  }
  std::vector<Source> roots;
  for (std::uint32_t r : tape_->results()) roots.push_back(source_of_register[r]);

  // Backward: live instructions (kept, and read by a live one or a root).
  std::vector<char> live(n, 0);
  std::vector<char> constant_live(constants.size(), 0);
  auto mark = [&](Source s) {
    if (is_instruction(s))
      live[static_cast<std::size_t>(s)] = 1;
    else if (s <= kConstant)
      constant_live[static_cast<std::size_t>(kConstant - s)] = 1;
  };
  for (Source r : roots) mark(r);
  for (std::size_t i = n; i-- > 0;) {
    if (!live[i]) continue;
    const int k = arity(code[i].op);
    if (k >= 1) mark(arg_a[i]);
    if (k >= 2) mark(arg_b[i]);
  }

  // Last reader of every live instruction's result; roots are read forever.
  constexpr std::size_t kForever = static_cast<std::size_t>(-1);
  std::vector<std::size_t> last_use(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!live[i]) continue;
    const int k = arity(code[i].op);
    if (k >= 1 && is_instruction(arg_a[i])) last_use[static_cast<std::size_t>(arg_a[i])] = i;
    if (k >= 2 && is_instruction(arg_b[i])) last_use[static_cast<std::size_t>(arg_b[i])] = i;
  }
  for (Source r : roots)
    if (is_instruction(r)) last_use[static_cast<std::size_t>(r)] = kForever;

  // Emit: variables in their fixed registers, live constants next, then the
  // live instructions with registers reused after their last read.
  Tape t;
  t.dimension_ = dimension;
  t.classifiers_ = tape_->classifiers_;
  t.registers_ = static_cast<std::size_t>(dimension);
  std::vector<std::uint32_t> constant_register(constants.size(), 0);
  for (std::size_t k = 0; k < constants.size(); ++k) {
    if (!constant_live[k]) continue;
    constant_register[k] = static_cast<std::uint32_t>(t.registers_++);  // never reused
    t.constants_.emplace_back(constant_register[k], constants[k]);
  }
  std::vector<std::uint32_t> reg(n, 0);
  auto register_of = [&](Source s) -> std::uint32_t {
    if (is_instruction(s)) return reg[static_cast<std::size_t>(s)];
    if (s <= kConstant) return constant_register[static_cast<std::size_t>(kConstant - s)];
    return Tape::variable_register(static_cast<int>(kVariable - s));
  };
  std::vector<std::uint32_t> free_registers;
  t.code_.reserve(static_cast<std::size_t>(std::count(live.begin(), live.end(), 1)));
  for (std::size_t i = 0; i < n; ++i) {
    if (!live[i]) continue;
    Instruction ins = code[i];
    const int k = arity(ins.op);
    if (k >= 1) ins.a = register_of(arg_a[i]);
    if (k >= 2) ins.b = register_of(arg_b[i]);
    // Free arguments read for the last time (once, if both are the same
    // value); the output may reuse one, as in Tape's compiler.
    if (k >= 1 && is_instruction(arg_a[i]) && last_use[static_cast<std::size_t>(arg_a[i])] == i)
      free_registers.push_back(ins.a);
    if (k >= 2 && arg_b[i] != arg_a[i] && is_instruction(arg_b[i]) && last_use[static_cast<std::size_t>(arg_b[i])] == i)
      free_registers.push_back(ins.b);
    if (!free_registers.empty()) {
      ins.out = free_registers.back();
      free_registers.pop_back();
    } else {
      ins.out = static_cast<std::uint32_t>(t.registers_++);
    }
    reg[i] = ins.out;
    t.code_.push_back(ins);
  }
  for (Source r : roots) t.results_.push_back(register_of(r));
  return t;
}

}  // namespace sage
