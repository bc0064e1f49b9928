#pragma once
// The table of operations: every node kind of the expression graph,
// declared once. Each row is (name, stable id, text name, arity). Ids are
// part of saved files and must never be reused or renumbered; add new rows
// with new ids. Evaluators, printing, differentiation and the test sweep
// over all operations are driven by this one list.

#include <array>
#include <cstdint>
#include <string_view>
#include <type_traits>

namespace sage {

// clang-format off
#define SAGE_OPCODES(X)                                                          \
  X(Const,    0, "const",    0) /* p0 = value */                                 \
  X(VarX,     1, "x",        0)                                                  \
  X(VarY,     2, "y",        0)                                                  \
  X(VarZ,     3, "z",        0)                                                  \
  X(Neg,     10, "neg",      1)                                                  \
  X(Square,  11, "square",   1)                                                  \
  X(Sqrt,    12, "sqrt",     1)                                                  \
  X(Exp,     13, "exp",      1)                                                  \
  X(Log,     14, "log",      1)                                                  \
  X(Sin,     15, "sin",      1)                                                  \
  X(Cos,     16, "cos",      1)                                                  \
  X(Abs,     17, "abs",      1)                                                  \
  X(Step,    18, "step",     1) /* Heaviside, step(0) = 1/2 */                   \
  X(PowInt,  19, "pow_int",  1) /* p0 = integer exponent */                      \
  X(PowReal, 20, "pow_real", 1) /* p0 = real exponent, base >= 0 */              \
  X(Add,     30, "add",      2)                                                  \
  X(Sub,     31, "sub",      2)                                                  \
  X(Mul,     32, "mul",      2)                                                  \
  X(Div,     33, "div",      2)                                                  \
  X(DivSafe, 34, "div_safe", 2) /* x / y, 0 where y = 0 */                       \
  X(Min,     35, "min",      2)                                                  \
  X(Max,     36, "max",      2)                                                  \
  X(Axpby,   37, "axpby",    2) /* p0 a + p1 b: halfplanes in two instructions */ \
  X(Offset,  38, "offset",   1) /* tapes only: a + p0, a constant added without its register */ \
  X(Scale,   39, "scale",    1) /* tapes only: a * p0, a constant factor without its register */ \
  X(RAnd,    50, "r_and",    2) /* R-conjunction; p0, p1 = RSystem */            \
  X(ROr,     51, "r_or",     2) /* R-disjunction; p0, p1 = RSystem */          \
  X(Classify, 60, "classify", 0) /* point membership, +1 / 0 / -1 */          \
  X(Patch,   61, "patch",    0) /* tapes only: a ChebyshevPatch standing in for a subtree */
// clang-format on

enum class Op : std::uint8_t {
#define SAGE_OP_ENUM(name, id, text, arity) name = id,
  SAGE_OPCODES(SAGE_OP_ENUM)
#undef SAGE_OP_ENUM
};

namespace detail {
// Arity by opcode (-1: no such operation): a table, since tape passes ask
// it for every instruction and a switch compiles to a chain of branches.
constexpr std::array<std::int8_t, 256> kArity = [] {
  std::array<std::int8_t, 256> table{};
  table.fill(-1);
#define SAGE_OP_ARITY(name, id, text, ar) table[id] = ar;
  SAGE_OPCODES(SAGE_OP_ARITY)
#undef SAGE_OP_ARITY
  return table;
}();
}  // namespace detail

constexpr int arity(Op op) { return detail::kArity[static_cast<std::uint8_t>(op)]; }

constexpr std::string_view op_name(Op op) {
  switch (op) {
#define SAGE_OP_NAME(name, id, text, ar) \
  case Op::name: return text;
    SAGE_OPCODES(SAGE_OP_NAME)
#undef SAGE_OP_NAME
  }
  return "?";
}

/// A compile-time operation, for code generic over the table.
template <Op op>
using OpTag = std::integral_constant<Op, op>;

/// Calls f(OpTag<op>{}): one switch turns a run-time operation into a
/// compile-time one, so a loop over many points can be decoded once
/// (evaluator.hpp) while each operation is still written only once.
template <class F>
constexpr decltype(auto) visit_op(Op op, F&& f) {
  switch (op) {
#define SAGE_OP_VISIT(name, id, text, ar) \
  case Op::name: return f(OpTag<Op::name>{});
    SAGE_OPCODES(SAGE_OP_VISIT)
#undef SAGE_OP_VISIT
  }
  return f(OpTag<Op::Const>{});  // not reached: the switch is exhaustive
}

/// Operations that appear in tapes only, never in expression graphs: the
/// far-field approximation (tape_specialization.hpp) puts patches there,
/// and compiling (tape.hpp) turns additions of constants into offsets and
/// products by them into scales.
constexpr bool tape_only(Op op) { return op == Op::Patch || op == Op::Offset || op == Op::Scale; }

/// Every operation, for sweeps in tests and tools.
constexpr Op kAllOps[] = {
#define SAGE_OP_LIST(name, id, text, ar) Op::name,
    SAGE_OPCODES(SAGE_OP_LIST)
#undef SAGE_OP_LIST
};

}  // namespace sage
