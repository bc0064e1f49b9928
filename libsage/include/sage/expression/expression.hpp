#pragma once
// Expr: the expression graph at the centre of sage.
//
// Geometry builds expressions, everything else consumes them. An Expr is a
// cheap handle to an immutable node (shared ownership: a node lives as
// long as any expression refers to it; subexpressions are shared, so the
// graph is a DAG). Expressions are built at run time, from files or code,
// with the usual operators and the functions of scalar.hpp:
//
//     Expr x = Expr::x(), y = Expr::y();
//     Expr disk = (1.0 - square(x) - square(y)) * 0.5;   // >= 0 inside
//     Expr both = r_and(disk, y, RSystem::r0());
//
// An Expr is not evaluated directly: compile it into a Tape (tape.hpp) and
// evaluate the tape with double, Tuple or Interval. Symbolic derivatives
// (derivative.hpp) are expressions too, which is how normalization and
// orthogonalized trimming get derivatives of every order.
//
// Construction folds constants and drops neutral elements (x + 0, x * 1,
// x * 0), so derivative graphs stay small.

#include <sage/expression/classifier.hpp>
#include <sage/expression/opcode.hpp>
#include <sage/scalars/rfunction.hpp>

#include <array>
#include <memory>
#include <string>

namespace sage {

class Expr;

/// A node of the graph. Immutable once built; owned by the Exprs that
/// refer to it.
struct Node {
  Op op = Op::Const;
  std::array<std::shared_ptr<const Node>, 2> args;
  std::array<double, 2> params{0.0, 0.0};
  std::shared_ptr<const PointClassifier> classifier;  // Op::Classify only

  Node() = default;
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;
  /// Iterative teardown, so that releasing a very deep graph cannot
  /// overflow the stack.
  ~Node();
};

class Expr {
 public:
  Expr() : Expr(0.0) {}
  Expr(double constant);  // NOLINT: implicit like a double

  static Expr x() { return var(0); }
  static Expr y() { return var(1); }
  static Expr z() { return var(2); }
  static Expr var(int index);
  /// A node with explicit operation, arguments and parameters (no folding
  /// beyond what the operation's own constructor does).
  static Expr make(Op op, const Expr& a, const Expr& b, double p0 = 0.0, double p1 = 0.0);
  static Expr make(Op op, const Expr& a, double p0 = 0.0) { return make(op, a, Expr(), p0); }
  /// Point membership classification xi(p) (classifier.hpp).
  static Expr classify(std::shared_ptr<const PointClassifier> classifier);

  Op op() const { return node_->op; }
  Expr arg(int i) const { return Expr(node_->args[i]); }
  double param(int i) const { return node_->params[i]; }
  const Node* id() const { return node_.get(); }
  bool is_constant() const { return node_->op == Op::Const; }
  bool is_constant(double value) const { return is_constant() && node_->params[0] == value; }
  double constant_value() const { return node_->params[0]; }
  const std::shared_ptr<const PointClassifier>& classifier() const { return node_->classifier; }
  RSystem rsystem() const { return {static_cast<RKind>(static_cast<int>(param(0))), param(1)}; }

  /// Highest variable index used + 1 (0 for a constant), i.e. the smallest
  /// dimension the expression can be evaluated in.
  int variables_used() const;
  /// Number of distinct nodes.
  std::size_t node_count() const;

 private:
  explicit Expr(std::shared_ptr<const Node> n) : node_(std::move(n)) {}
  std::shared_ptr<const Node> node_;
};

Expr operator+(const Expr& a, const Expr& b);
Expr operator-(const Expr& a, const Expr& b);
Expr operator*(const Expr& a, const Expr& b);
Expr operator/(const Expr& a, const Expr& b);
Expr operator-(const Expr& a);
inline Expr& operator+=(Expr& a, const Expr& b) { return a = a + b; }
inline Expr& operator*=(Expr& a, const Expr& b) { return a = a * b; }

Expr square(const Expr& a);
Expr sqrt(const Expr& a);
Expr exp(const Expr& a);
Expr log(const Expr& a);
Expr sin(const Expr& a);
Expr cos(const Expr& a);
Expr abs(const Expr& a);
Expr step(const Expr& a);
Expr pow_int(const Expr& a, int n);
Expr pow_real(const Expr& a, double r);
Expr div_safe(const Expr& a, const Expr& b);
Expr min(const Expr& a, const Expr& b);
Expr max(const Expr& a, const Expr& b);
Expr clamp_nonneg(const Expr& a);

/// R-function nodes (one node each; evaluators apply rfunction.hpp).
Expr r_and(const Expr& a, const Expr& b, const RSystem& s);
Expr r_or(const Expr& a, const Expr& b, const RSystem& s);

}  // namespace sage
