#include <sage/evaluator.hpp>
#include <sage/formula.hpp>

#include <gtest/gtest.h>

TEST(Smoke, FormulaValue) {
  const sage::Tape tape(sage::parse_formula("x^2 + y^2 - 1", 2), 2);
  sage::Evaluator<double> eval(tape);
  EXPECT_DOUBLE_EQ(eval.at({1.0, 2.0}), 4.0);
}
