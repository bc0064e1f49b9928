#include <sage/expression/expression.hpp>

#include <cmath>
#include <stdexcept>
#include <unordered_set>
#include <vector>

namespace sage {

Node::~Node() {
  // Move uniquely owned children onto a heap stack before they die, so the
  // recursion depth of destruction stays 1 whatever the depth of the graph.
  std::vector<std::shared_ptr<const Node>> pending;
  auto adopt = [&pending](std::array<std::shared_ptr<const Node>, 2>& children) {
    for (auto& a : children)
      if (a && a.use_count() == 1) pending.push_back(std::move(a));
  };
  adopt(const_cast<Node*>(this)->args);
  while (!pending.empty()) {
    std::shared_ptr<const Node> n = std::move(pending.back());
    pending.pop_back();
    adopt(const_cast<Node*>(n.get())->args);
  }
}

namespace {
std::shared_ptr<const Node> new_node(Op op, std::shared_ptr<const Node> a, std::shared_ptr<const Node> b, double p0,
                                     double p1) {
  auto n = std::make_shared<Node>();
  n->op = op;
  n->args = {std::move(a), std::move(b)};
  n->params = {p0, p1};
  return n;
}

bool both_constant(const Expr& a, const Expr& b) { return a.is_constant() && b.is_constant(); }
}  // namespace

Expr::Expr(double constant) : node_(new_node(Op::Const, nullptr, nullptr, constant, 0.0)) {}

Expr Expr::var(int index) {
  static const Op vars[] = {Op::VarX, Op::VarY, Op::VarZ};
  if (index < 0 || index > 2) throw std::out_of_range("variable index must be 0, 1 or 2");
  return Expr(new_node(vars[index], nullptr, nullptr, 0.0, 0.0));
}

Expr Expr::make(Op op, const Expr& a, const Expr& b, double p0, double p1) {
  if (tape_only(op) || op == Op::Classify)
    throw std::invalid_argument(std::string(op_name(op)) + " nodes are not made with Expr::make");
  const int n = arity(op);
  return Expr(new_node(op, n >= 1 ? a.node_ : nullptr, n >= 2 ? b.node_ : nullptr, p0, p1));
}

Expr Expr::classify(std::shared_ptr<const PointClassifier> classifier) {
  if (!classifier) throw std::invalid_argument("classify: no classifier");
  auto n = std::make_shared<Node>();
  n->op = Op::Classify;
  n->classifier = std::move(classifier);
  return Expr(std::shared_ptr<const Node>(std::move(n)));
}

int Expr::variables_used() const {
  int used = 0;
  std::unordered_set<const Node*> seen;
  std::vector<const Node*> stack{node_.get()};
  while (!stack.empty()) {
    const Node* n = stack.back();
    stack.pop_back();
    if (!seen.insert(n).second) continue;
    if (n->op == Op::VarX) used = std::max(used, 1);
    if (n->op == Op::VarY) used = std::max(used, 2);
    if (n->op == Op::VarZ) used = std::max(used, 3);
    if (n->op == Op::Classify) used = std::max(used, n->classifier->dimension());
    for (const auto& a : n->args)
      if (a) stack.push_back(a.get());
  }
  return used;
}

std::size_t Expr::node_count() const {
  std::unordered_set<const Node*> seen;
  std::vector<const Node*> stack{node_.get()};
  while (!stack.empty()) {
    const Node* n = stack.back();
    stack.pop_back();
    if (!seen.insert(n).second) continue;
    for (const auto& a : n->args)
      if (a) stack.push_back(a.get());
  }
  return seen.size();
}

// ---- construction with folding ---------------------------------------------

namespace {
// u * c or c * u with a constant c: the parts of an Axpby.
bool scaled(const Expr& e, Expr& u, double& c) {
  if (e.op() != Op::Mul) return false;
  if (e.arg(1).is_constant()) {
    u = e.arg(0), c = e.arg(1).constant_value();
    return true;
  }
  if (e.arg(0).is_constant()) {
    u = e.arg(1), c = e.arg(0).constant_value();
    return true;
  }
  return false;
}
}  // namespace

Expr operator+(const Expr& a, const Expr& b) {
  if (both_constant(a, b)) return a.constant_value() + b.constant_value();
  if (a.is_constant(0.0)) return b;
  if (b.is_constant(0.0)) return a;
  // a u + b v in one instruction (halfplanes, linear maps).
  Expr u, v;
  double cu = 0, cv = 0;
  if (scaled(a, u, cu) && scaled(b, v, cv)) return Expr::make(Op::Axpby, u, v, cu, cv);
  return Expr::make(Op::Add, a, b);
}

Expr operator-(const Expr& a, const Expr& b) {
  if (both_constant(a, b)) return a.constant_value() - b.constant_value();
  if (b.is_constant(0.0)) return a;
  if (a.is_constant(0.0)) return -b;
  Expr u, v;
  double cu = 0, cv = 0;
  if (scaled(a, u, cu) && scaled(b, v, cv)) return Expr::make(Op::Axpby, u, v, cu, -cv);
  return Expr::make(Op::Sub, a, b);
}

Expr operator*(const Expr& a, const Expr& b) {
  if (both_constant(a, b)) return a.constant_value() * b.constant_value();
  if (a.is_constant(0.0) || b.is_constant(0.0)) return 0.0;
  if (a.is_constant(1.0)) return b;
  if (b.is_constant(1.0)) return a;
  if (a.is_constant(-1.0)) return -b;
  if (b.is_constant(-1.0)) return -a;
  return Expr::make(Op::Mul, a, b);
}

Expr operator/(const Expr& a, const Expr& b) {
  if (both_constant(a, b)) return a.constant_value() / b.constant_value();
  if (a.is_constant(0.0) && !b.is_constant(0.0)) return 0.0;
  if (b.is_constant(1.0)) return a;
  return Expr::make(Op::Div, a, b);
}

Expr operator-(const Expr& a) {
  if (a.is_constant()) return -a.constant_value();
  if (a.op() == Op::Neg) return a.arg(0);
  return Expr::make(Op::Neg, a);
}

namespace {
// Unary operation with constant folding through the double version.
template <class F>
Expr unary(Op op, const Expr& a, F fold, double p0 = 0.0) {
  if (a.is_constant()) return fold(a.constant_value());
  return Expr::make(op, a, p0);
}
}  // namespace

Expr square(const Expr& a) {
  return unary(Op::Square, a, [](double v) { return v * v; });
}
Expr sqrt(const Expr& a) {
  return unary(Op::Sqrt, a, [](double v) { return std::sqrt(v); });
}
Expr exp(const Expr& a) {
  return unary(Op::Exp, a, [](double v) { return std::exp(v); });
}
Expr log(const Expr& a) {
  return unary(Op::Log, a, [](double v) { return std::log(v); });
}
Expr sin(const Expr& a) {
  return unary(Op::Sin, a, [](double v) { return std::sin(v); });
}
Expr cos(const Expr& a) {
  return unary(Op::Cos, a, [](double v) { return std::cos(v); });
}
Expr abs(const Expr& a) {
  return unary(Op::Abs, a, [](double v) { return std::abs(v); });
}
Expr step(const Expr& a) {
  return unary(Op::Step, a, [](double v) { return sage::step(v); });
}

Expr pow_int(const Expr& a, int n) {
  if (n == 0) return 1.0;
  if (n == 1) return a;
  if (n == 2) return square(a);
  return unary(
      Op::PowInt, a, [n](double v) { return sage::pow_int(v, n); }, n);
}

Expr pow_real(const Expr& a, double r) {
  if (r == std::floor(r) && std::abs(r) < 0x1p20) return pow_int(a, static_cast<int>(r));
  if (r == 0.5) return sqrt(a);
  return unary(
      Op::PowReal, a, [r](double v) { return sage::pow_real(v, r); }, r);
}

Expr div_safe(const Expr& a, const Expr& b) {
  if (both_constant(a, b)) return sage::div_safe(a.constant_value(), b.constant_value());
  if (a.is_constant(0.0)) return 0.0;
  return Expr::make(Op::DivSafe, a, b);
}

Expr min(const Expr& a, const Expr& b) {
  if (both_constant(a, b)) return sage::min(a.constant_value(), b.constant_value());
  return Expr::make(Op::Min, a, b);
}
Expr max(const Expr& a, const Expr& b) {
  if (both_constant(a, b)) return sage::max(a.constant_value(), b.constant_value());
  return Expr::make(Op::Max, a, b);
}
Expr clamp_nonneg(const Expr& a) { return max(a, 0.0); }

Expr r_and(const Expr& a, const Expr& b, const RSystem& s) {
  if (both_constant(a, b)) return r_combine(a.constant_value(), b.constant_value(), s, -1.0);
  return Expr::make(Op::RAnd, a, b, static_cast<int>(s.kind), s.parameter);
}
Expr r_or(const Expr& a, const Expr& b, const RSystem& s) {
  if (both_constant(a, b)) return r_combine(a.constant_value(), b.constant_value(), s, +1.0);
  return Expr::make(Op::ROr, a, b, static_cast<int>(s.kind), s.parameter);
}

}  // namespace sage
