#include <sage/expression/boolean_form.hpp>

#include <algorithm>
#include <array>
#include <unordered_map>

namespace sage {

namespace {

/// What a node of the walk becomes: a formula node, or a constant.
struct Folded {
  bool is_constant;
  bool value;          // when is_constant
  std::uint32_t node;  // otherwise
};

/// Whether `e` keeps the sign of its Boolean argument (+1), flips it (-1),
/// or is not a sign-keeping operation of one argument (0); `arg` is set to
/// the argument.
int sign_map(const Expr& e, Expr& arg) {
  switch (e.op()) {
    case Op::Neg: arg = e.arg(0); return -1;
    case Op::Mul:
    case Op::Div: {
      // x * c, c * x and x / c with a constant c != 0.
      const bool first_constant = e.op() == Op::Mul && e.arg(0).is_constant();
      const Expr c = first_constant ? e.arg(0) : e.arg(1);
      if (!c.is_constant() || !(c.constant_value() != 0.0)) return 0;
      arg = first_constant ? e.arg(1) : e.arg(0);
      return c.constant_value() > 0 ? 1 : -1;
    }
    default: return 0;
  }
}

enum class Join { None, And, Or };

Join join_of(const Expr& e) {
  switch (e.op()) {
    case Op::RAnd:
    case Op::Min: return Join::And;
    case Op::ROr:
    case Op::Max: return Join::Or;
    default: return Join::None;
  }
}

}  // namespace

BooleanFormula BooleanFormula::constant(bool value) {
  BooleanFormula f;
  f.constant_ = value;
  return f;
}

BooleanFormula BooleanFormula::piece(std::uint32_t index) {
  BooleanFormula f;
  f.nodes_.push_back({Kind::Piece, index, 0});
  return f;
}

namespace {

/// Appends g's nodes to `nodes`, renumbered; returns g's root there.
std::uint32_t append_nodes(std::vector<BooleanFormula::Node>& nodes, const std::vector<BooleanFormula::Node>& g) {
  const auto shift = static_cast<std::uint32_t>(nodes.size());
  for (BooleanFormula::Node n : g) {
    if (n.kind != BooleanFormula::Kind::Piece) {
      n.a += shift;
      n.b += shift;
    }
    nodes.push_back(n);
  }
  return static_cast<std::uint32_t>(nodes.size() - 1);
}

}  // namespace

BooleanFormula BooleanFormula::negation(const BooleanFormula& f) {
  if (f.is_constant()) return constant(!f.constant_);
  BooleanFormula out = f;
  out.nodes_.push_back({Kind::Not, static_cast<std::uint32_t>(f.nodes_.size() - 1), 0});
  return out;
}

BooleanFormula BooleanFormula::join(Kind kind, const BooleanFormula& f, const BooleanFormula& g) {
  const bool absorbing = kind == Kind::Or;  // OR: true absorbs, false is neutral; AND the reverse
  if (f.is_constant()) return f.constant_ == absorbing ? f : g;
  if (g.is_constant()) return g.constant_ == absorbing ? g : f;
  BooleanFormula out = f;
  const auto left = static_cast<std::uint32_t>(f.nodes_.size() - 1);
  const std::uint32_t right = append_nodes(out.nodes_, g.nodes_);
  out.nodes_.push_back({kind, left, right});
  return out;
}

BooleanFormula BooleanFormula::conjunction(const BooleanFormula& f, const BooleanFormula& g) {
  return join(Kind::And, f, g);
}

BooleanFormula BooleanFormula::disjunction(const BooleanFormula& f, const BooleanFormula& g) {
  return join(Kind::Or, f, g);
}

namespace {

/// The formula's nodes evaluated bottom-up into `value` (one per node).
template <class Inside>
bool evaluate_nodes(const std::vector<BooleanFormula::Node>& nodes, const Inside& inside, char* value) {
  using Kind = BooleanFormula::Kind;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const BooleanFormula::Node& n = nodes[k];
    switch (n.kind) {
      case Kind::Piece: value[k] = inside(n.a) ? 1 : 0; break;
      case Kind::Not: value[k] = value[n.a] ? 0 : 1; break;
      case Kind::And: value[k] = value[n.a] && value[n.b] ? 1 : 0; break;
      case Kind::Or: value[k] = value[n.a] || value[n.b] ? 1 : 0; break;
    }
  }
  return value[nodes.size() - 1] != 0;
}

/// Small formulas (a cell's few pieces) on the stack: the cut-cell rules
/// evaluate them at every segment of every line.
template <class Inside>
bool evaluate(const std::vector<BooleanFormula::Node>& nodes, const Inside& inside) {
  constexpr std::size_t kOnStack = 64;
  if (nodes.size() <= kOnStack) {
    std::array<char, kOnStack> value;
    return evaluate_nodes(nodes, inside, value.data());
  }
  std::vector<char> value(nodes.size());
  return evaluate_nodes(nodes, inside, value.data());
}

}  // namespace

bool BooleanFormula::holds(const std::function<bool(std::size_t)>& inside) const {
  if (is_constant()) return constant_;
  return evaluate(nodes_, inside);
}

bool BooleanFormula::holds(const std::vector<char>& inside) const {
  if (is_constant()) return constant_;
  return evaluate(nodes_, [&](std::size_t i) { return inside[i] != 0; });
}

BooleanFormula BooleanFormula::restricted(const std::function<int(std::size_t)>& sign) const {
  if (is_constant()) return *this;
  BooleanFormula out;
  std::vector<Folded> folded(nodes_.size());
  auto add = [&](Node n) {
    out.nodes_.push_back(n);
    return Folded{false, false, static_cast<std::uint32_t>(out.nodes_.size() - 1)};
  };
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    const Node& n = nodes_[k];
    switch (n.kind) {
      case Kind::Piece: {
        const int s = sign(n.a);
        folded[k] = s != 0 ? Folded{true, s > 0, 0} : add({Kind::Piece, n.a, 0});
        break;
      }
      case Kind::Not: {
        const Folded& a = folded[n.a];
        folded[k] = a.is_constant ? Folded{true, !a.value, 0} : add({Kind::Not, a.node, 0});
        break;
      }
      case Kind::And:
      case Kind::Or: {
        const Folded &a = folded[n.a], &b = folded[n.b];
        const bool absorbing = n.kind == Kind::Or;  // OR: true absorbs; AND: false absorbs
        if ((a.is_constant && a.value == absorbing) || (b.is_constant && b.value == absorbing)) {
          folded[k] = Folded{true, absorbing, 0};
        } else if (a.is_constant) {
          folded[k] = b;  // the neutral constant drops out
        } else if (b.is_constant) {
          folded[k] = a;
        } else {
          folded[k] = add({n.kind, a.node, b.node});
        }
        break;
      }
    }
  }
  const Folded& root = folded.back();
  if (root.is_constant) return constant(root.value);
  // Nodes that only a folded-away branch read are unreachable: drop them,
  // so that pieces() names only what the formula reads.
  std::vector<char> reached(out.nodes_.size(), 0);
  reached[root.node] = 1;
  for (std::size_t k = root.node + 1; k-- > 0;) {
    if (!reached[k]) continue;
    const Node& n = out.nodes_[k];
    if (n.kind == Kind::Not || n.kind == Kind::And || n.kind == Kind::Or) reached[n.a] = 1;
    if (n.kind == Kind::And || n.kind == Kind::Or) reached[n.b] = 1;
  }
  BooleanFormula compact;
  std::vector<std::uint32_t> renumber(out.nodes_.size(), 0);
  for (std::size_t k = 0; k <= root.node; ++k) {
    if (!reached[k]) continue;
    Node n = out.nodes_[k];
    if (n.kind != Kind::Piece) {
      n.a = renumber[n.a];
      n.b = renumber[n.b];
    }
    renumber[k] = static_cast<std::uint32_t>(compact.nodes_.size());
    compact.nodes_.push_back(n);
  }
  return compact;
}

std::vector<std::uint32_t> BooleanFormula::pieces() const {
  std::vector<std::uint32_t> out;
  for (const Node& n : nodes_)
    if (n.kind == Kind::Piece) out.push_back(n.a);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

BooleanForm boolean_form(const Expr& field) {
  // An explicit stack (Boolean trees of polygons and meshes can be deep):
  // each frame is a node of the walk, visited twice (children, then itself).
  BooleanForm form;
  std::unordered_map<const Node*, std::uint32_t> piece_of;
  std::unordered_map<const Node*, BooleanFormula> done;
  struct Frame {
    Expr e;
    bool expanded;
  };
  std::vector<Frame> stack{{field, false}};
  auto piece_formula = [&](const Expr& e) {
    const auto [it, added] = piece_of.emplace(e.id(), static_cast<std::uint32_t>(form.pieces.size()));
    if (added) form.pieces.push_back(e);
    return BooleanFormula::piece(it->second);
  };
  while (!stack.empty()) {
    Frame frame = stack.back();
    const Expr& e = frame.e;
    if (done.count(e.id())) {
      stack.pop_back();
      continue;
    }
    Expr arg;
    const int sign = sign_map(e, arg);
    const Join join = join_of(e);
    if (!frame.expanded) {
      stack.back().expanded = true;
      if (sign != 0) stack.push_back({arg, false});
      if (join != Join::None) {
        stack.push_back({e.arg(1), false});
        stack.push_back({e.arg(0), false});
      }
      continue;
    }
    stack.pop_back();
    BooleanFormula f;
    if (sign != 0) {
      const BooleanFormula& a = done.at(arg.id());
      f = sign > 0 ? a : BooleanFormula::negation(a);
    } else if (join == Join::And) {
      f = BooleanFormula::conjunction(done.at(e.arg(0).id()), done.at(e.arg(1).id()));
    } else if (join == Join::Or) {
      f = BooleanFormula::disjunction(done.at(e.arg(0).id()), done.at(e.arg(1).id()));
    } else if (e.is_constant()) {
      f = BooleanFormula::constant(e.constant_value() >= 0.0);
    } else {
      f = piece_formula(e);
    }
    done.emplace(e.id(), std::move(f));
  }
  form.formula = done.at(field.id());
  return form;
}

}  // namespace sage
