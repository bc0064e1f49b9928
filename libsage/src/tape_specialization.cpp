#include <sage/evaluator.hpp>
#include <sage/tape_specialization.hpp>

namespace sage {

namespace {

bool is_min(const Instruction& ins) {
  return ins.op == Op::Min || (ins.op == Op::RAnd && static_cast<RKind>(static_cast<int>(ins.p0)) == RKind::MinMax);
}
bool is_max(const Instruction& ins) {
  return ins.op == Op::Max || (ins.op == Op::ROr && static_cast<RKind>(static_cast<int>(ins.p0)) == RKind::MinMax);
}

// A value of the specialized program: a variable, a constant, or the result
// of a kept instruction of the original tape.
struct Value {
  enum class Kind : unsigned char { Variable, Constant, Instruction } kind;
  double constant = 0.0;       // Kind::Constant
  std::uint32_t index = 0;     // variable number, or instruction position
  std::uint32_t a = 0, b = 0;  // argument values, Kind::Instruction
};

}  // namespace

TapeSpecializer::TapeSpecializer(const Tape& tape)
    : tape_(&tape), registers_(tape.register_count()), fate_(tape.code().size()), constant_(tape.code().size()) {
  for (const auto& [r, c] : tape.constants()) registers_[r] = Interval(c);
  for (const Instruction& ins : tape.code())
    prunable_ += is_min(ins) || is_max(ins) || ins.op == Op::Step || ins.op == Op::Classify;
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

  // Values, in an order where arguments come before their readers.
  std::vector<Value> values;
  std::vector<std::uint32_t> value_of_register(tape_->register_count(), 0);
  auto add = [&values](Value v) {
    values.push_back(v);
    return static_cast<std::uint32_t>(values.size() - 1);
  };
  for (int i = 0; i < dimension; ++i)
    value_of_register[i] = add({Value::Kind::Variable, 0.0, static_cast<std::uint32_t>(i)});
  for (const auto& [r, c] : tape_->constants()) value_of_register[r] = add({Value::Kind::Constant, c});
  for (std::size_t i = 0; i < code.size(); ++i) {
    const Instruction& ins = code[i];
    const std::uint32_t a = value_of_register[ins.a], b = value_of_register[ins.b];
    std::uint32_t v = 0;
    switch (fate_[i]) {
      case Fate::Keep: v = add({Value::Kind::Instruction, 0.0, static_cast<std::uint32_t>(i), a, b}); break;
      case Fate::FirstArgument: v = a; break;
      case Fate::SecondArgument: v = b; break;
      case Fate::Constant: v = add({Value::Kind::Constant, constant_[i]}); break;
    }
    value_of_register[ins.out] = v;
  }

  // Live values: the roots and, backwards, the arguments of live instructions.
  std::vector<std::uint32_t> roots;
  for (std::uint32_t r : tape_->results()) roots.push_back(value_of_register[r]);
  std::vector<bool> live(values.size(), false);
  for (std::uint32_t r : roots) live[r] = true;
  constexpr std::size_t kForever = static_cast<std::size_t>(-1);
  std::vector<std::size_t> last_use(values.size(), 0);
  for (std::uint32_t r : roots) last_use[r] = kForever;
  for (std::size_t v = values.size(); v-- > 0;) {
    if (!live[v] || values[v].kind != Value::Kind::Instruction) continue;
    const int n = arity(code[values[v].index].op);
    if (n >= 1) live[values[v].a] = true;
    if (n >= 2) live[values[v].b] = true;
  }
  for (std::size_t v = 0; v < values.size(); ++v) {
    if (!live[v] || values[v].kind != Value::Kind::Instruction) continue;
    const int n = arity(code[values[v].index].op);
    for (int k = 0; k < n; ++k) {
      const std::uint32_t arg = k == 0 ? values[v].a : values[v].b;
      if (last_use[arg] != kForever) last_use[arg] = v;
    }
  }

  // Emit the live instructions with registers reused after their last read.
  Tape t;
  t.dimension_ = dimension;
  t.classifiers_ = tape_->classifiers_;
  t.registers_ = static_cast<std::size_t>(dimension);
  std::vector<std::uint32_t> reg(values.size(), 0);
  std::vector<std::uint32_t> free_registers;
  for (std::size_t v = 0; v < values.size(); ++v) {
    if (!live[v]) continue;
    const Value& value = values[v];
    if (value.kind == Value::Kind::Variable) {
      reg[v] = Tape::variable_register(static_cast<int>(value.index));
    } else if (value.kind == Value::Kind::Constant) {
      reg[v] = static_cast<std::uint32_t>(t.registers_++);  // never reused
      t.constants_.emplace_back(reg[v], value.constant);
    } else {
      Instruction ins = code[value.index];
      const int n = arity(ins.op);
      if (n >= 1) ins.a = reg[value.a];
      if (n >= 2) ins.b = reg[value.b];
      // Free arguments read for the last time (once, if both are the same
      // value); the output may reuse one, as in Tape's compiler.
      for (int k = 0; k < n; ++k) {
        const std::uint32_t arg = k == 0 ? value.a : value.b;
        const bool duplicate = k == 1 && value.b == value.a;
        if (!duplicate && last_use[arg] == v && values[arg].kind == Value::Kind::Instruction)
          free_registers.push_back(reg[arg]);
      }
      if (!free_registers.empty()) {
        ins.out = free_registers.back();
        free_registers.pop_back();
      } else {
        ins.out = static_cast<std::uint32_t>(t.registers_++);
      }
      reg[v] = ins.out;
      t.code_.push_back(ins);
    }
  }
  for (std::uint32_t r : roots) t.results_.push_back(reg[r]);
  return t;
}

}  // namespace sage
