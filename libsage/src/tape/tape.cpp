#include <sage/tape/tape.hpp>

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace sage {

namespace {

// Node -> position in the tape's order, by open addressing (linear probing
// over a power-of-two table). A large mesh's field has millions of nodes:
// std::unordered_map's allocation per entry and rehashing made up most of
// Tape::Tape (bunny00, 2.1M instructions: this table took 2 s off it).
class NodePositions {
 public:
  static constexpr std::uint32_t kNone = UINT32_MAX;

  NodePositions() { grow(); }

  std::uint32_t find(const Node* n) const {
    for (std::size_t k = slot(n);; k = (k + 1) & mask_) {
      if (keys_[k] == n) return values_[k];
      if (!keys_[k]) return kNone;
    }
  }
  std::uint32_t& operator[](const Node* n) {
    if (2 * (size_ + 1) > keys_.size()) grow();
    std::size_t k = slot(n);
    for (; keys_[k] && keys_[k] != n; k = (k + 1) & mask_) {
    }
    if (!keys_[k]) {
      keys_[k] = n;
      values_[k] = kNone;
      ++size_;
    }
    return values_[k];
  }

 private:
  std::size_t slot(const Node* n) const {
    auto x = static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(n));
    x ^= x >> 33;  // a 64-bit mixer: node addresses share their low bits
    x *= 0xff51afd7ed558ccdull;
    x ^= x >> 33;
    return static_cast<std::size_t>(x) & mask_;
  }
  void grow() {
    std::vector<const Node*> keys = std::move(keys_);
    std::vector<std::uint32_t> values = std::move(values_);
    const std::size_t size = std::max<std::size_t>(1024, 2 * keys.size());
    keys_.assign(size, nullptr);
    values_.assign(size, kNone);
    mask_ = size - 1;
    size_ = 0;
    for (std::size_t k = 0; k < keys.size(); ++k)
      if (keys[k]) (*this)[keys[k]] = values[k];
  }

  std::vector<const Node*> keys_;
  std::vector<std::uint32_t> values_;
  std::size_t mask_ = 0, size_ = 0;
};

// The nodes below `roots`, every argument before its readers; position[n]
// is n's index in the result.
std::vector<const Node*> topological_order(const std::vector<Expr>& roots, NodePositions& position) {
  constexpr std::uint32_t kOnStack = NodePositions::kNone - 1;
  std::vector<const Node*> order;
  std::vector<std::pair<const Node*, int>> stack;  // node, next argument to visit
  for (const Expr& r : roots) stack.emplace_back(r.id(), 0);
  while (!stack.empty()) {
    auto& [n, next] = stack.back();
    if (next == 0 && position.find(n) != NodePositions::kNone) {
      stack.pop_back();
      continue;
    }
    position[n] = kOnStack;
    if (next < arity(n->op)) {
      const Node* child = n->args[static_cast<std::size_t>(next++)].get();
      if (position.find(child) == NodePositions::kNone) stack.emplace_back(child, 0);
      continue;
    }
    position[n] = static_cast<std::uint32_t>(order.size());
    order.push_back(n);
    stack.pop_back();
  }
  return order;
}
}  // namespace

Tape::Tape(const std::vector<Expr>& roots, int dimension) : dimension_(dimension) {
  if (dimension < 1 || dimension > 3) throw std::invalid_argument("tape dimension must be 1, 2 or 3");
  NodePositions position;
  const std::vector<const Node*> order = topological_order(roots, position);
  if (order.size() >= NodePositions::kNone - 1) throw std::length_error("a tape holds fewer than 2^32 - 2 nodes");
  auto arg = [](const Node* n, int k) { return n->args[static_cast<std::size_t>(k)].get(); };
  auto at = [&](const Node* n) { return static_cast<std::size_t>(position.find(n)); };

  // Last reader of every node (by position in `order`); roots live forever.
  std::vector<std::size_t> last_use(order.size(), 0);
  for (std::size_t i = 0; i < order.size(); ++i)
    for (int k = 0; k < arity(order[i]->op); ++k) last_use[at(arg(order[i], k))] = i;
  for (const Expr& r : roots) last_use[at(r.id())] = order.size();

  constexpr std::uint32_t kNoRegister = UINT32_MAX;
  std::vector<std::uint32_t> reg(order.size(), kNoRegister);
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
  auto register_of = [&](const Node* n) -> std::uint32_t {
    std::uint32_t& r = reg[at(n)];
    if (r != kNoRegister) return r;
    if (n->op != Op::Const) throw std::logic_error("Tape: a node read before it is computed");
    r = static_cast<std::uint32_t>(registers_++);
    constants_.emplace_back(r, n->params[0]);
    return r;
  };

  for (std::size_t i = 0; i < order.size(); ++i) {
    const Node* e = order[i];
    switch (e->op) {
      case Op::VarX:
      case Op::VarY:
      case Op::VarZ: {
        const int v = static_cast<int>(e->op) - static_cast<int>(Op::VarX);
        if (v >= dimension)
          throw std::invalid_argument("the expression uses variable " + std::string(op_name(e->op)) +
                                      " but the model is " + std::to_string(dimension) + "D");
        reg[i] = variable_register(v);
        continue;
      }
      case Op::Const: continue;  // register_of() gives it one if read from a register
      default: break;
    }
    Instruction ins{e->op, 0, 0, 0, e->params[0], e->params[1]};
    const int args = arity(e->op);
    const bool offset =
        (e->op == Op::Add || e->op == Op::Sub) && arg(e, 1)->op == Op::Const && arg(e, 0)->op != Op::Const;
    const bool offset_first = e->op == Op::Add && arg(e, 0)->op == Op::Const && arg(e, 1)->op != Op::Const;
    if (e->op == Op::Classify) {
      if (e->classifier->dimension() != dimension)
        throw std::invalid_argument("a point classifier of dimension " + std::to_string(e->classifier->dimension()) +
                                    " in a " + std::to_string(dimension) + "D tape");
      classifiers_.push_back(e->classifier);
      ins.classifier = e->classifier.get();
    }
    // u c: u * p0, the same numbers (a mesh field has a constant factor per
    // face plane, whose registers would outnumber the working ones).
    const bool scale = e->op == Op::Mul && arg(e, 1)->op == Op::Const && arg(e, 0)->op != Op::Const;
    if (offset || offset_first) {
      // u + c, u - c and c + u: u + p0 (the same numbers, as u - c = u + (-c)).
      const double c = arg(e, offset ? 1 : 0)->params[0];
      ins = Instruction{Op::Offset, 0, register_of(arg(e, offset ? 0 : 1)), 0, e->op == Op::Sub ? -c : c, 0.0};
    } else if (scale) {
      ins = Instruction{Op::Scale, 0, register_of(arg(e, 0)), 0, arg(e, 1)->params[0], 0.0};
    } else {
      if (args >= 1) ins.a = register_of(arg(e, 0));
      if (args >= 2) ins.b = register_of(arg(e, 1));
    }
    // Free the arguments whose last reader is this instruction, then
    // allocate the output: it may take an argument's register, which is
    // safe because every evaluator reads its arguments before writing.
    for (int k = 0; k < args; ++k) {
      const Node* a = arg(e, k);
      const bool duplicate = k == 1 && a == arg(e, 0);
      const bool fixed = a->op == Op::Const || a->op == Op::VarX || a->op == Op::VarY || a->op == Op::VarZ;
      if (duplicate || fixed) continue;
      const std::size_t position_of_a = at(a);
      if (last_use[position_of_a] == i) free_registers.push_back(reg[position_of_a]);
    }
    ins.out = allocate();
    reg[i] = ins.out;
    code_.push_back(ins);
  }
  for (const Expr& r : roots) results_.push_back(register_of(r.id()));
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
