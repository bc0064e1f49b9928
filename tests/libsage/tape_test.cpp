// Claims of tape.hpp / evaluator.hpp / derivative.hpp:
//  - every op in kAllOps evaluates to its mathematical definition (an
//    independent reference) and its tuple first derivatives equal both the
//    symbolic derivative() evaluated in double and finite differences of
//    the reference, at random points in the op's smooth domain (sweep);
//  - register reuse keeps register_count at the width of the graph, not its
//    size (a 2000-node chain needs a handful of registers);
//  - constants added to or subtracted from a value become offsets, with no
//    register (a 1000-halfplane R0 tree has none), and the same numbers;
//  - several roots compile together, share subexpressions and give the same
//    values as separate tapes;
//  - using a variable beyond the dimension throws.

#include "test_support.hpp"

#include <sage/expression/derivative.hpp>
#include <sage/scalars/rfunction.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <gtest/gtest.h>

#include <set>

namespace sage {
namespace {

using test::Point;

TEST(Tape, SweepEveryOpValueAndFirstDerivatives) {
  // Every op of the table must appear in the sweep.
  std::set<Op> covered;
  auto rng = test::make_rng(90);
  for (const test::OpCase& c : test::op_cases(true)) {
    SCOPED_TRACE(c.name);
    covered.insert(c.op);
    const Expr f = c.build(Expr::x(), Expr::y(), Expr::z());
    ASSERT_EQ(f.op(), c.op) << "the case must put its op at the root";
    const Tape tape(f, 3);
    const std::vector<Expr> grad = gradient(f, 3);
    const Tape grad_tape(grad, 3);
    Evaluator<double> dv(tape), gv(grad_tape);
    Evaluator<Tuple<3, 1>> tv(tape);
    Evaluator<Tuple<3, 2>> tv2(tape);
    int tested = 0;
    for (int attempt = 0; attempt < 20000 && tested < 300; ++attempt) {
      const Point p = test::random_point(rng, -2, 2);
      if (!c.smooth(p)) continue;
      ++tested;
      const double ref = c.reference(p);
      const double tol = 1e-13 * (1 + std::abs(ref));
      EXPECT_NEAR(dv.at(p), ref, tol);
      const auto t = tv.at(p);
      EXPECT_NEAR(t.value(), ref, tol);
      EXPECT_NEAR(tv2.at(p).value(), ref, tol);
      gv.evaluate(p.data());
      for (int axis = 0; axis < 3; ++axis) {
        const double tuple_d = t.gradient()[axis];
        const double symbolic_d = gv.result(static_cast<std::size_t>(axis));
        const double fd = test::central_difference(c.reference, p, axis, 1e-4);
        EXPECT_NEAR(tuple_d, symbolic_d, 1e-12 * (1 + std::abs(symbolic_d))) << "axis " << axis;
        EXPECT_NEAR(tuple_d, fd, 1e-6 * (1 + std::abs(fd))) << "axis " << axis;
        // Order-2 tuples agree with order-1 tuples on the first derivatives.
        EXPECT_NEAR(tv2.at(p).gradient()[axis], tuple_d, 1e-13 * (1 + std::abs(tuple_d)));
      }
    }
    EXPECT_GE(tested, 300) << "domain too small for the sweep";
  }
  for (Op op : kAllOps) {
    if (tape_only(op)) continue;
    EXPECT_TRUE(covered.count(op)) << "op " << op_name(op) << " is not in the sweep";
  }
}

TEST(Tape, SecondDerivativesOfEveryOpMatchNestedSymbolicDerivatives) {
  auto rng = test::make_rng(91);
  for (const test::OpCase& c : test::op_cases(true)) {
    SCOPED_TRACE(c.name);
    const Expr f = c.build(Expr::x(), Expr::y(), Expr::z());
    std::vector<Expr> second;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) second.push_back(derivative(derivative(f, i), j));
    const Tape tape(f, 3), st(second, 3);
    Evaluator<Tuple<3, 2>> tv(tape);
    Evaluator<double> sv(st);
    int tested = 0;
    for (int attempt = 0; attempt < 20000 && tested < 50; ++attempt) {
      const Point p = test::random_point(rng, -2, 2);
      if (!c.smooth(p)) continue;
      ++tested;
      const auto t = tv.at(p);
      sv.evaluate(p.data());
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          MultiIndex<3> al{0, 0, 0};
          ++al[i];
          ++al[j];
          const double s = sv.result(static_cast<std::size_t>(3 * i + j));
          EXPECT_NEAR(t.derivative(al), s, 1e-11 * (1 + std::abs(s))) << i << j;
        }
    }
  }
}

TEST(Tape, RegisterReuseKeepsALongChainNarrow) {
  const Expr x = Expr::x(), y = Expr::y();
  Expr f = x;
  for (int i = 0; i < 500; ++i) f = sin(f) * 0.9 + y * 0.1 - square(f) * 0.01;  // ~4 nodes per step
  ASSERT_GT(f.node_count(), 1500u);
  const Tape tape(f, 2);
  // Every constant read from a register keeps one of its own (loaded once),
  // so count the working registers: those left for intermediate values.
  const std::size_t working = tape.register_count() - tape.constants().size();
  EXPECT_LE(working, 8u) << "registers: " << tape.register_count() << ", constants: " << tape.constants().size();
  EXPECT_GT(tape.code().size(), 1500u);
  // And it still computes the chain correctly.
  const double px = 0.3, py = -0.7;
  double v = px;
  for (int i = 0; i < 500; ++i) v = std::sin(v) * 0.9 + py * 0.1 - v * v * 0.01;
  Evaluator<double> ev(tape);
  EXPECT_NEAR(ev.at({px, py, 0}), v, 1e-12);
}

TEST(Tape, RegisterReuseOnAWideBalancedTree) {
  // A balanced sum of 1024 leaves needs about log2(1024) live values.
  std::vector<Expr> leaves;
  for (int i = 0; i < 1024; ++i) leaves.push_back(sin(Expr::x() * static_cast<double>(i + 1)));
  while (leaves.size() > 1) {
    std::vector<Expr> next;
    for (std::size_t i = 0; i < leaves.size(); i += 2) next.push_back(leaves[i] + leaves[i + 1]);
    leaves = next;
  }
  const Tape tape(leaves[0], 2);
  EXPECT_LE(tape.register_count() - tape.constants().size(), 2u + 12u);
  double expected = 0;
  for (int i = 0; i < 1024; ++i) expected += std::sin(0.01 * (i + 1));
  Evaluator<double> ev(tape);
  EXPECT_NEAR(ev.at({0.01, 0, 0}), expected, 1e-10);
}

TEST(Tape, AddedConstantsAreOffsetsWithoutRegisters) {
  const Expr x = Expr::x(), y = Expr::y();
  const Expr s = sin(x);
  const double px = 0.4, sx = std::sin(px);
  // u + c, u - c, c + u: offsets, exact; c - u reads c from a register.
  const Expr forms[] = {s + 2.5, s - 2.5, Expr(2.5) + s, Expr(2.5) - s};
  const double expected[] = {sx + 2.5, sx - 2.5, 2.5 + sx, 2.5 - sx};
  for (int k = 0; k < 4; ++k) {
    const Tape tape(forms[k], 2);
    Evaluator<double> ev(tape);
    EXPECT_EQ(ev.at({px, 0, 0}), expected[k]) << "form " << k;
    EXPECT_EQ(tape.code().back().op, k < 3 ? Op::Offset : Op::Sub) << "form " << k;
    EXPECT_EQ(tape.constants().size(), k < 3 ? 0u : 1u) << "form " << k;
  }
  // A polygon-sized tree: 1000 halfplanes n . p - c under R0.
  const double qx = 0.3, qy = -0.2;
  std::vector<Expr> halfplanes;
  std::vector<double> values;
  for (int i = 0; i < 1000; ++i) {
    const double angle = 0.5 + 0.00628 * i, c = 1.0 + 0.001 * i;  // no axis-parallel lines
    halfplanes.push_back(x * std::cos(angle) + y * std::sin(angle) - c);
    values.push_back(qx * std::cos(angle) + qy * std::sin(angle) - c);
  }
  const Tape tape(r_conjunction_n(halfplanes, RSystem::r0()), 2);
  std::size_t offsets = 0;
  for (const Instruction& ins : tape.code()) offsets += ins.op == Op::Offset;
  EXPECT_EQ(offsets, 1000u);
  EXPECT_EQ(tape.constants().size(), 0u);
  EXPECT_LE(tape.register_count(), 2u + 16u);
  const double reference = r_conjunction_n(values, RSystem::r0());
  Evaluator<double> ev(tape);
  EXPECT_NEAR(ev.at({qx, qy, 0}), reference, 1e-12 * std::abs(reference));
}

TEST(Tape, ConstantFactorsAreScalesAndConstantsComeLast) {
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  // u c is a Scale without a register, with the numbers of the product
  // that reads c from one (c u stays such a product), to second order.
  const Expr u = sin(x) * y + z;
  const Tape scaled(u * -1.75, 3), product(Expr(-1.75) * u, 3);
  EXPECT_EQ(scaled.code().back().op, Op::Scale);
  EXPECT_TRUE(scaled.constants().empty());
  EXPECT_EQ(product.code().back().op, Op::Mul);
  Evaluator<Tuple<3, 2>> a(scaled), b(product);
  for (const std::array<double, 3>& p : {std::array<double, 3>{0.3, -0.2, 0.7}, {-1.1, 0.5, 0.0}, {2.0, 3.0, -4.0}}) {
    a.evaluate(p.data());
    b.evaluate(p.data());
    for (int c = 0; c < Tuple<3, 2>::size; ++c) EXPECT_EQ(a.result(0).c[c], b.result(0).c[c]) << "coefficient " << c;
  }
  // A mesh-sized set of planes n . p + d: no constant registers at all.
  std::vector<Expr> planes;
  for (int i = 0; i < 500; ++i) {
    const double t = 0.01 * i;
    planes.push_back(x * std::cos(t) + y * std::sin(t) + z * (0.5 - 0.001 * i) - 1.0);
  }
  const Tape mesh_like(r_conjunction_n(planes, RSystem::r0()), 3);
  EXPECT_TRUE(mesh_like.constants().empty());
  EXPECT_LE(mesh_like.register_count(), 3u + 16u);
  // Constants read from registers are numbered after every working
  // register, so the working ones lie together.
  std::vector<Expr> differences;
  for (int i = 0; i < 50; ++i) differences.push_back(Expr(0.1 * (i + 1)) - sin(x * (1.0 + 0.01 * i)));
  const Tape tape(r_conjunction_n(differences, RSystem::r0()), 2);
  ASSERT_EQ(tape.constants().size(), 50u);
  std::uint32_t working = 0;
  for (const Instruction& ins : tape.code()) working = std::max(working, ins.out);
  for (const auto& [r, c] : tape.constants()) EXPECT_GT(r, working);
  Evaluator<double> ev(tape);
  std::vector<double> values;
  for (int i = 0; i < 50; ++i) values.push_back(0.1 * (i + 1) - std::sin(0.4 * (1.0 + 0.01 * i)));
  EXPECT_EQ(ev.at({0.4, 0, 0}), r_conjunction_n(values, RSystem::r0()));
}

TEST(Tape, SameArgumentTwiceAndOutputAliasing) {
  // f * f, f + f, f / f: the output may reuse an argument register.
  const Expr x = Expr::x();
  const Expr f = sin(x) + 2.0;
  const Expr g = (f * f) + (f / f) - Expr::make(Op::Add, f, f);
  const Tape tape(g, 2);
  Evaluator<double> e2(tape);
  const double s = std::sin(0.4) + 2;
  EXPECT_NEAR(e2.at({0.4, 0, 0}), s * s + 1 - 2 * s, 1e-14);
}

TEST(Tape, MultipleRootsShareSubexpressions) {
  const Expr x = Expr::x(), y = Expr::y(), z = Expr::z();
  const Expr shared = exp(x * y) + cos(z);
  const Expr a = shared * 2.0, b = sqrt(square(shared) + 1.0), c = shared - x;
  const Tape all({a, b, c, x}, 3);
  const Tape ta(a, 3), tb(b, 3), tc(c, 3);
  EXPECT_LT(all.code().size(), ta.code().size() + tb.code().size() + tc.code().size());
  ASSERT_EQ(all.results().size(), 4u);
  Evaluator<double> e(all), ea(ta), eb(tb), ec(tc);
  Evaluator<Tuple<3, 2>> et(all), eta(ta);
  auto rng = test::make_rng(92);
  for (int i = 0; i < 100; ++i) {
    const Point p = test::random_point(rng, -1, 1);
    e.evaluate(p.data());
    const double s = std::exp(p[0] * p[1]) + std::cos(p[2]);
    EXPECT_DOUBLE_EQ(e.result(0), ea.at(p));
    EXPECT_DOUBLE_EQ(e.result(1), eb.at(p));
    EXPECT_DOUBLE_EQ(e.result(2), ec.at(p));
    EXPECT_NEAR(e.result(0), 2 * s, 1e-14 * (1 + s));
    EXPECT_NEAR(e.result(1), std::sqrt(s * s + 1), 1e-14 * (1 + s));
    EXPECT_NEAR(e.result(2), s - p[0], 1e-14 * (1 + s));
    EXPECT_EQ(e.result(3), p[0]);
    et.evaluate(p.data());
    const auto ta_t = eta.at(p);
    for (int k = 0; k < ta_t.size; ++k) EXPECT_DOUBLE_EQ(et.result(0).c[k], ta_t.c[k]);
  }
  // A root may be a constant or a bare variable.
  const Tape consts({Expr(3.5), y}, 2);
  Evaluator<double> ec2(consts);
  ec2.evaluate(std::array<double, 3>{1, 2, 0}.data());
  EXPECT_EQ(ec2.result(0), 3.5);
  EXPECT_EQ(ec2.result(1), 2.0);
}

TEST(Tape, ProducerLinksFollowRegisterReuse) {
  // Replaying the code with each argument taken from its producer's
  // result (or the variable) must give what the registers give.
  const Expr x = Expr::x(), y = Expr::y();
  Expr f = 0.5;
  for (int i = 0; i < 12; ++i) f = min(f, sqrt(square(x - 0.1 * i) + square(y)) * (1.0 + 0.01 * i));
  const Tape tape({f, x * y}, 2);
  const auto& code = tape.code();
  ASSERT_EQ(tape.producers().size(), code.size());
  const std::array<double, 3> p{0.37, -0.21, 0.0};
  Evaluator<double> ev(tape);
  ev.evaluate(p.data());
  std::vector<double> regs(tape.register_count()), by_link(code.size());
  regs[0] = p[0];
  regs[1] = p[1];
  for (const auto& [r, c] : tape.constants()) regs[r] = c;
  std::vector<std::uint32_t> readers(code.size(), 0);
  for (std::size_t i = 0; i < code.size(); ++i) {
    const Instruction& ins = code[i];
    auto argument = [&](int k, std::uint32_t reg) {
      const std::uint32_t producer = tape.producers()[i][k];
      if (producer == Tape::kInput) return regs[reg];  // a variable or constant: never overwritten
      ++readers[producer];
      return by_link[producer];
    };
    const int k = arity(ins.op);
    const double a = k >= 1 ? argument(0, ins.a) : 0.0, b = k >= 2 ? argument(1, ins.b) : 0.0;
    by_link[i] = apply<double>(ins, a, b);
  }
  for (std::size_t r = 0; r < 2; ++r) {
    const std::uint32_t producer = tape.result_producers()[r];
    ASSERT_NE(producer, Tape::kInput);
    EXPECT_EQ(by_link[producer], ev.result(r));
    readers[producer] += 2;
  }
  EXPECT_EQ(readers, tape.readers());
}

TEST(Tape, DimensionCheck) {
  const Expr z = Expr::z();
  EXPECT_THROW(Tape(z + 1.0, 2), std::invalid_argument);
  EXPECT_THROW(Tape(sin(Expr::y()), 1), std::invalid_argument);
  EXPECT_THROW(Tape(Expr::x(), 0), std::invalid_argument);
  EXPECT_THROW(Tape(Expr::x(), 4), std::invalid_argument);
  EXPECT_NO_THROW(Tape(z + 1.0, 3));
  EXPECT_THROW(Expr::var(3), std::out_of_range);
  EXPECT_EQ((Expr::x() * Expr::z()).variables_used(), 3);
  EXPECT_EQ(Expr(2.0).variables_used(), 0);
}

TEST(Expression, ConstructionFoldsConstantsAndNeutralElements) {
  const Expr x = Expr::x();
  EXPECT_TRUE((Expr(2.0) + Expr(3.0)).is_constant(5.0));
  EXPECT_EQ((x + 0.0).id(), x.id());
  EXPECT_EQ((x * 1.0).id(), x.id());
  EXPECT_TRUE((x * 0.0).is_constant(0.0));
  EXPECT_EQ((-(-x)).id(), x.id());
  EXPECT_TRUE(sqrt(Expr(4.0)).is_constant(2.0));
  EXPECT_EQ(pow_real(x, 0.5).op(), Op::Sqrt);
  EXPECT_EQ(pow_real(x, 3.0).op(), Op::PowInt);
  EXPECT_EQ(pow_int(x, 2).op(), Op::Square);
  // The derivative of a constant-only graph folds to a constant.
  EXPECT_TRUE(derivative(square(x) * 3.0, 1).is_constant(0.0));
  // Very deep graphs are released without recursion (no stack overflow).
  Expr deep = x;
  for (int i = 0; i < 200000; ++i) deep = sin(deep);
  EXPECT_EQ(deep.op(), Op::Sin);
}

}  // namespace
}  // namespace sage
