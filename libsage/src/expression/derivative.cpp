#include <sage/expression/derivative.hpp>

#include <stdexcept>
#include <unordered_map>

namespace sage {

Expr expand_rfunction(const Expr& f) {
  if (f.op() != Op::RAnd && f.op() != Op::ROr) throw std::invalid_argument("not an R-function node");
  return r_combine<Expr>(f.arg(0), f.arg(1), f.rsystem(), f.op() == Op::RAnd ? -1.0 : 1.0);
}

namespace {

/// Differentiates many expressions with respect to one variable, sharing
/// the memo so common subexpressions are differentiated once.
class Differentiator {
 public:
  explicit Differentiator(int var) : var_(var) {}

  Expr operator()(const Expr& root) {
    // Iterative post-order: a node is differentiated once all the nodes its
    // rule needs are done.
    std::vector<Expr> stack{root};
    while (!stack.empty()) {
      const Expr f = stack.back();
      if (memo_.count(f.id())) {
        stack.pop_back();
        continue;
      }
      bool ready = true;
      for (const Expr& dep : dependencies(f))
        if (!memo_.count(dep.id())) {
          stack.push_back(dep);
          ready = false;
        }
      if (!ready) continue;
      stack.pop_back();
      memo_.emplace(f.id(), rule(f));
    }
    return memo_.at(root.id());
  }

 private:
  std::vector<Expr> dependencies(const Expr& f) {
    if (f.op() == Op::RAnd || f.op() == Op::ROr) return {expansion(f)};
    std::vector<Expr> deps;
    for (int i = 0; i < arity(f.op()); ++i) deps.push_back(f.arg(i));
    return deps;
  }

  Expr expansion(const Expr& f) {
    auto it = expansions_.find(f.id());
    if (it == expansions_.end()) it = expansions_.emplace(f.id(), expand_rfunction(f)).first;
    return it->second;
  }

  const Expr& d(const Expr& e) const { return memo_.at(e.id()); }

  Expr rule(const Expr& f) {
    const int n = arity(f.op());
    const Expr u = n >= 1 ? f.arg(0) : Expr();
    const Expr v = n >= 2 ? f.arg(1) : Expr();
    switch (f.op()) {
      case Op::Const: return 0.0;
      case Op::VarX: return var_ == 0 ? 1.0 : 0.0;
      case Op::VarY: return var_ == 1 ? 1.0 : 0.0;
      case Op::VarZ: return var_ == 2 ? 1.0 : 0.0;
      case Op::Neg: return -d(u);
      case Op::Square: return 2.0 * u * d(u);
      case Op::Sqrt: return div_safe(d(u), 2.0 * f);
      case Op::Exp: return f * d(u);
      case Op::Log: return d(u) / u;
      case Op::Sin: return cos(u) * d(u);
      case Op::Cos: return -(sin(u) * d(u));
      case Op::Abs: return (2.0 * step(u) - 1.0) * d(u);
      case Op::Step:
      case Op::Classify: return 0.0;  // piecewise constant
      case Op::PowInt: {
        const int k = static_cast<int>(f.param(0));
        return static_cast<double>(k) * pow_int(u, k - 1) * d(u);
      }
      case Op::PowReal: return f.param(0) * div_safe(f * d(u), u);
      case Op::Add: return d(u) + d(v);
      case Op::Axpby: return d(u) * f.param(0) + d(v) * f.param(1);
      case Op::Sub: return d(u) - d(v);
      case Op::Mul: return d(u) * v + u * d(v);
      case Op::Div: return (d(u) - f * d(v)) / v;
      case Op::DivSafe: return div_safe(d(u) - f * d(v), v);
      case Op::Min: return d(u) + step(u - v) * (d(v) - d(u));
      case Op::Max: return d(u) + step(v - u) * (d(v) - d(u));
      case Op::RAnd:
      case Op::ROr: return d(expansion(f));
      case Op::Patch:
      case Op::Offset:
      case Op::Scale: break;  // tapes only
    }
    throw std::logic_error("derivative: unknown operation");
  }

  int var_;
  std::unordered_map<const Node*, Expr> memo_;
  std::unordered_map<const Node*, Expr> expansions_;  // keeps expansions alive
};

}  // namespace

Expr derivative(const Expr& f, int var) { return Differentiator(var)(f); }

std::vector<Expr> gradient(const Expr& f, int dimension) {
  std::vector<Expr> g;
  for (int v = 0; v < dimension; ++v) g.push_back(derivative(f, v));
  return g;
}

}  // namespace sage
