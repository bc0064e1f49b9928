// Claims of formula.hpp: the grammar has the usual precedence, ^ binds
// tightest and is right-associative, -x^2 is -(x^2), integer exponents
// are exact powers (negative bases allowed), and malformed input throws
// FormulaError with the 1-based column of the offending character (the
// expected columns below are counted by hand from the grammar); z is
// rejected in a 2D model.

#include "test_support.hpp"

#include <sage/expression/formula.hpp>

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

// Every primitive of paper 003's table (appendix A) is writable as a
// formula; each parses and matches the same function written in C++.
TEST(Formula, Paper003PrimitiveTable) {
  using std::pow;
  using std::sin;
  using std::sqrt;
  struct Case {
    const char* name;
    const char* text;
    double (*f)(double, double, double);
  };
  const Case cases[] = {
      {"sphere", "x^2 + y^2 + z^2 - 0.7^2", [](double x, double y, double z) { return x * x + y * y + z * z - 0.49; }},
      {"pseudo-cube", "x^500 + y^500 + z^500 - 0.7^2",
       [](double x, double y, double z) { return pow(x, 500) + pow(y, 500) + pow(z, 500) - 0.49; }},
      {"cylinder", "x^2 + y^2 - 1", [](double x, double y, double) { return x * x + y * y - 1; }},
      {"torus", "(1 - sqrt(x^2 + y^2))^2 + z^2 - .125",
       [](double x, double y, double z) { return pow(1 - sqrt(x * x + y * y), 2) + z * z - .125; }},
      {"4-bretzel", "(x^2*(1.21 - x^2)^2*(3.8 - x^2)^3 - 10*y^2)^2 / 10 + 60*z^2 - 2",
       [](double x, double y, double z) {
         return pow(x * x * pow(1.21 - x * x, 2) * pow(3.8 - x * x, 3) - 10 * y * y, 2) / 10 + 60 * z * z - 2;
       }},
      {"tangle", "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8",
       [](double x, double y, double z) {
         return pow(x, 4) - 5 * x * x + pow(y, 4) - 5 * y * y + pow(z, 4) - 5 * z * z + 11.8;
       }},
      {"decocube",
       "((x^2 + y^2 - 0.8^2)^2 + (z^2 - 1)^2) * ((y^2 + z^2 - 0.8^2)^2 + (x^2 - 1)^2) * "
       "((z^2 + x^2 - 0.8^2)^2 + (y^2 - 1)^2) - 0.02",
       [](double x, double y, double z) {
         const double a = pow(x * x + y * y - 0.64, 2) + pow(z * z - 1, 2);
         const double b = pow(y * y + z * z - 0.64, 2) + pow(x * x - 1, 2);
         const double c = pow(z * z + x * x - 0.64, 2) + pow(y * y - 1, 2);
         return a * b * c - 0.02;
       }},
      {"superquadric", "x^200 + (.5*y^4 + .5*z^4)^4 - 1",
       [](double x, double y, double z) { return pow(x, 200) + pow(.5 * pow(y, 4) + .5 * pow(z, 4), 4) - 1; }},
      {"ellipsoid", ".25*x^2 + .25*y^2 + z^2 - 1",
       [](double x, double y, double z) { return .25 * x * x + .25 * y * y + z * z - 1; }},
      {"heart", "(2*x^2 + y^2 + z^2 - 1)^3 - (.1*x^2 + y^2)*z^3",
       [](double x, double y, double z) {
         return pow(2 * x * x + y * y + z * z - 1, 3) - (.1 * x * x + y * y) * pow(z, 3);
       }},
      {"citrus", "x^2 + z^2 - 4*y^3*(1 - .5*y)^3",
       [](double x, double y, double z) { return x * x + z * z - 4 * pow(y, 3) * pow(1 - .5 * y, 3); }},
      {"trigonometric", "(1 - sqrt(x^2 + y^2))^2 + sin(z)^3 - .125",
       [](double x, double y, double z) { return pow(1 - sqrt(x * x + y * y), 2) + pow(sin(z), 3) - .125; }},
  };
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.05, 1.05);
  for (const Case& c : cases) {
    const Expr e = parse_formula(c.text, 3);
    for (int k = 0; k < 20; ++k) {
      const double x = u(rng), y = u(rng), z = u(rng);
      const double expected = c.f(x, y, z);
      EXPECT_NEAR(test::eval(e, {x, y, z}, 3), expected, 1e-12 * (1 + std::abs(expected))) << c.name;
    }
  }
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

namespace sage {
namespace {

TEST(Formula, DeepNestingIsAnErrorNotACrash) {
  const std::string deep = std::string(200000, '(') + "x" + std::string(200000, ')');
  EXPECT_THROW(parse_formula(deep, 2), FormulaError);
  const std::string signs = std::string(200000, '-') + "x";
  EXPECT_THROW(parse_formula(signs, 2), FormulaError);
  const std::string fine = std::string(100, '(') + "x" + std::string(100, ')');
  EXPECT_NO_THROW(parse_formula(fine, 2));
}

}  // namespace
}  // namespace sage
