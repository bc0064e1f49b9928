// Claims of formula.hpp: the grammar has the usual precedence, ^ binds
// tightest and is right-associative, -x^2 is -(x^2), integer exponents
// are exact powers (negative bases allowed), and malformed input throws
// FormulaError with the 1-based column of the offending character (the
// expected columns below are counted by hand from the grammar); z is
// rejected in a 2D model.

#include "test_support.hpp"

#include <sage/formula.hpp>

#include <gtest/gtest.h>

namespace sage {
namespace {

double value(const std::string& text, double x = 0, double y = 0, double z = 0, int dim = 3) {
  return test::eval(parse_formula(text, dim), {x, y, z}, dim);
}

std::size_t error_column(const std::string& text, int dim = 2) {
  try {
    parse_formula(text, dim);
  } catch (const FormulaError& e) {
    EXPECT_NE(std::string(e.what()).find("column " + std::to_string(e.column())), std::string::npos);
    return e.column();
  }
  ADD_FAILURE() << "'" << text << "' parsed without error";
  return 0;
}

TEST(Formula, Precedence) {
  EXPECT_EQ(value("1 + 2 * 3"), 7.0);
  EXPECT_EQ(value("(1 + 2) * 3"), 9.0);
  EXPECT_EQ(value("8 / 4 / 2"), 1.0);    // left-associative
  EXPECT_EQ(value("8 - 4 - 2"), 2.0);    // left-associative
  EXPECT_EQ(value("2 * 3 ^ 2"), 18.0);   // ^ before *
  EXPECT_EQ(value("2 ^ 3 ^ 2"), 512.0);  // right-associative: 2^(3^2)
  EXPECT_EQ(value("2 ^ -1"), 0.5);
  EXPECT_EQ(value("-x^2", 3.0), -9.0);  // -(x^2)
  EXPECT_EQ(value("(-x)^2", 3.0), 9.0);
  EXPECT_EQ(value("- - x", 3.0), 3.0);
  EXPECT_EQ(value("+x", 3.0), 3.0);
  EXPECT_EQ(value("(-2)^3"), -8.0);  // exact integer power of a negative base
  EXPECT_EQ(value("x^500", -1.0), 1.0);
  EXPECT_EQ(value("1e-3 * 1000"), 1.0);
  EXPECT_EQ(value(".5 + 0.25"), 0.75);
  EXPECT_DOUBLE_EQ(value("pi"), M_PI);
  EXPECT_DOUBLE_EQ(value("e"), M_E);
  EXPECT_DOUBLE_EQ(value("x^1.5", 4.0), 8.0);
}

TEST(Formula, FunctionsAndVariables) {
  const double x = 0.7, y = -0.3, z = 1.9;
  EXPECT_NEAR(value("sqrt(x^2 + y^2 + z^2) - 1", x, y, z), std::sqrt(x * x + y * y + z * z) - 1, 1e-15);
  EXPECT_NEAR(value("exp(x) * log(z) + sin(y) - cos(x*y)", x, y, z),
              std::exp(x) * std::log(z) + std::sin(y) - std::cos(x * y), 1e-15);
  EXPECT_EQ(value("abs(y) + min(x, y) + max(x, z)", x, y, z), std::abs(y) + y + z);
  EXPECT_NEAR(value("pow(z, x)", x, y, z), std::pow(z, x), 1e-15);
  EXPECT_NEAR(value("z ^ x", x, y, z), std::pow(z, x), 1e-15);  // non-constant exponent: exp(x log z)
  EXPECT_NEAR(value("pow(z, 2)", x, y, z), z * z, 1e-15);
  EXPECT_NEAR(value("  x\t*  y ", x, y, z), x * y, 1e-15);
  // z is accepted in 3D.
  EXPECT_NO_THROW(parse_formula("x + y + z", 3));
}

TEST(Formula, ErrorColumns) {
  EXPECT_EQ(error_column("1 + * 2"), 5u);  // '*' where an operand should be
  EXPECT_EQ(error_column("sin(x"), 6u);    // end of input: expected ')'
  EXPECT_EQ(error_column("(x + y"), 7u);
  EXPECT_EQ(error_column("1 +"), 4u);  // end of input: expected an operand
  EXPECT_EQ(error_column(""), 1u);
  EXPECT_EQ(error_column("x y"), 3u);  // unexpected 'y'
  EXPECT_EQ(error_column("3 $"), 3u);
  EXPECT_EQ(error_column("2 * foo(x)"), 5u);  // unknown function at its name
  EXPECT_EQ(error_column("x + w"), 5u);       // unknown name
  EXPECT_EQ(error_column("max(x)"), 1u);      // wrong number of arguments
  EXPECT_EQ(error_column("1 + sqrt(x, y)"), 5u);
  EXPECT_EQ(error_column("x + z"), 5u);  // z in a 2D model
  EXPECT_EQ(error_column("sin(z)", 2), 5u);
  EXPECT_EQ(error_column("1e999"), 1u);  // number out of range
  EXPECT_EQ(error_column("x )"), 3u);
  EXPECT_THROW(parse_formula("x + z", 2), FormulaError);
  EXPECT_THROW(parse_formula("x + z", 2), std::runtime_error);  // FormulaError is a runtime_error
}

}  // namespace
}  // namespace sage
