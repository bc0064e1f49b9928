#include <sage/tape/tape.hpp>

#include <stdexcept>
#include <string>
#include <unordered_map>

namespace sage {

namespace {
std::vector<Expr> topological_order(const std::vector<Expr>& roots) {
  std::vector<Expr> order;
  std::unordered_map<const Node*, bool> done;  // false: on the stack, true: emitted
  std::vector<std::pair<Expr, int>> stack;     // node, next argument to visit
  for (const Expr& r : roots) stack.emplace_back(r, 0);
  while (!stack.empty()) {
    auto& [e, next] = stack.back();
    if (next == 0 && done.count(e.id())) {
      stack.pop_back();
      continue;
    }
    done.emplace(e.id(), false);
    if (next < arity(e.op())) {
      Expr child = e.arg(next++);
      if (!done.count(child.id())) stack.emplace_back(child, 0);
      continue;
    }
    done[e.id()] = true;
    order.push_back(e);
    stack.pop_back();
  }
  return order;
}
}  // namespace

Tape::Tape(const std::vector<Expr>& roots, int dimension) : dimension_(dimension) {
  if (dimension < 1 || dimension > 3) throw std::invalid_argument("tape dimension must be 1, 2 or 3");
  const std::vector<Expr> order = topological_order(roots);

  // Last reader of every node (by position in `order`); roots live forever.
  std::unordered_map<const Node*, std::size_t> last_use;
  for (std::size_t i = 0; i < order.size(); ++i) {
    for (int k = 0; k < arity(order[i].op()); ++k) last_use[order[i].arg(k).id()] = i;
  }
  for (const Expr& r : roots) last_use[r.id()] = order.size();

  std::unordered_map<const Node*, std::uint32_t> reg;
  std::vector<std::uint32_t> free_registers;
  registers_ = static_cast<std::size_t>(dimension);
  auto allocate = [&]() -> std::uint32_t {
    if (!free_registers.empty()) {
      const std::uint32_t r = free_registers.back();
      free_registers.pop_back();
      return r;
    }
    return static_cast<std::uint32_t>(registers_++);
  };
  // A constant gets its register when something reads it from one (never
  // reused). Large CSG trees add one constant per halfplane: as offsets
  // they need none, and batch evaluators do not stream a register of
  // identical lanes per halfplane through the cache.
  auto register_of = [&](const Expr& e) -> std::uint32_t {
    if (e.op() != Op::Const || reg.count(e.id())) return reg.at(e.id());
    const auto r = static_cast<std::uint32_t>(registers_++);
    constants_.emplace_back(r, e.constant_value());
    return reg[e.id()] = r;
  };

  for (std::size_t i = 0; i < order.size(); ++i) {
    const Expr& e = order[i];
    switch (e.op()) {
      case Op::VarX:
      case Op::VarY:
      case Op::VarZ: {
        const int v = static_cast<int>(e.op()) - static_cast<int>(Op::VarX);
        if (v >= dimension)
          throw std::invalid_argument("the expression uses variable " + std::string(op_name(e.op())) +
                                      " but the model is " + std::to_string(dimension) + "D");
        reg[e.id()] = variable_register(v);
        continue;
      }
      case Op::Const: continue;  // register_of() gives it one if read from a register
      default: break;
    }
    Instruction ins{e.op(), 0, 0, 0, e.param(0), e.param(1)};
    const bool offset =
        (e.op() == Op::Add || e.op() == Op::Sub) && e.arg(1).op() == Op::Const && e.arg(0).op() != Op::Const;
    const bool offset_first = e.op() == Op::Add && e.arg(0).op() == Op::Const && e.arg(1).op() != Op::Const;
    if (e.op() == Op::Classify) {
      if (e.classifier()->dimension() != dimension)
        throw std::invalid_argument("a point classifier of dimension " + std::to_string(e.classifier()->dimension()) +
                                    " in a " + std::to_string(dimension) + "D tape");
      classifiers_.push_back(e.classifier());
      ins.classifier = e.classifier().get();
    }
    // u c: u * p0, the same numbers (a mesh field has a constant factor per
    // face plane, whose registers would outnumber the working ones).
    const bool scale = e.op() == Op::Mul && e.arg(1).op() == Op::Const && e.arg(0).op() != Op::Const;
    if (offset || offset_first) {
      // u + c, u - c and c + u: u + p0 (the same numbers, as u - c = u + (-c)).
      const double c = e.arg(offset ? 1 : 0).constant_value();
      ins = Instruction{Op::Offset, 0, register_of(e.arg(offset ? 0 : 1)), 0, e.op() == Op::Sub ? -c : c, 0.0};
    } else if (scale) {
      ins = Instruction{Op::Scale, 0, register_of(e.arg(0)), 0, e.arg(1).constant_value(), 0.0};
    } else {
      if (arity(e.op()) >= 1) ins.a = register_of(e.arg(0));
      if (arity(e.op()) >= 2) ins.b = register_of(e.arg(1));
    }
    // Free the arguments whose last reader is this instruction, then
    // allocate the output: it may take an argument's register, which is
    // safe because every evaluator reads its arguments before writing.
    for (int k = 0; k < arity(e.op()); ++k) {
      const Expr arg = e.arg(k);
      const bool duplicate = k == 1 && arg.id() == e.arg(0).id();
      const Op aop = arg.op();
      const bool fixed = aop == Op::Const || aop == Op::VarX || aop == Op::VarY || aop == Op::VarZ;
      if (!duplicate && !fixed && last_use.at(arg.id()) == i) free_registers.push_back(reg.at(arg.id()));
    }
    ins.out = allocate();
    reg[e.id()] = ins.out;
    code_.push_back(ins);
  }
  for (const Expr& r : roots) results_.push_back(register_of(r));
  constants_last();
  link();
}

void Tape::constants_last() {
  // Constants took registers as they were first read, between the working
  // ones. Renumbered after them, the working registers of a tape with many
  // constants (a mesh field has one per face plane) lie together: the lanes
  // a batch evaluator streams stay in its caches.
  std::vector<char> constant(registers_, 0);
  for (const auto& [r, c] : constants_) constant[r] = 1;
  std::vector<std::uint32_t> renumbered(registers_);
  auto next = static_cast<std::uint32_t>(dimension_);
  for (std::size_t r = 0; r < registers_; ++r)
    if (r < static_cast<std::size_t>(dimension_))
      renumbered[r] = static_cast<std::uint32_t>(r);
    else if (!constant[r])
      renumbered[r] = next++;
  for (auto& [r, c] : constants_) {
    renumbered[r] = next++;
    r = renumbered[r];
  }
  for (Instruction& ins : code_) {
    const int k = arity(ins.op);
    if (k >= 1) ins.a = renumbered[ins.a];
    if (k >= 2) ins.b = renumbered[ins.b];
    ins.out = renumbered[ins.out];
  }
  for (std::uint32_t& r : results_) r = renumbered[r];
}

void Tape::link() {
  // The producer of each register as the code runs: registers are reused,
  // so an argument's producer is the last instruction to write it before.
  std::vector<std::uint32_t> producer_of_register(registers_, kInput);
  producers_.resize(code_.size());
  readers_.assign(code_.size(), 0);
  for (std::size_t i = 0; i < code_.size(); ++i) {
    const Instruction& ins = code_[i];
    const int k = arity(ins.op);
    producers_[i] = {k >= 1 ? producer_of_register[ins.a] : kInput, k >= 2 ? producer_of_register[ins.b] : kInput};
    for (int j = 0; j < k; ++j)
      if (producers_[i][j] != kInput) ++readers_[producers_[i][j]];
    producer_of_register[ins.out] = static_cast<std::uint32_t>(i);
  }
  result_producers_.clear();
  for (std::uint32_t r : results_) {
    result_producers_.push_back(producer_of_register[r]);
    if (producer_of_register[r] != kInput) readers_[producer_of_register[r]] += 2;  // read forever
  }
}

}  // namespace sage
