#include <sage/expression/formula.hpp>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace sage {

namespace {

// Recursive descent over the grammar
//   sum     := product (('+' | '-') product)*
//   product := unary (('*' | '/') unary)*
//   unary   := '-' unary | '+' unary | power
//   power   := primary ('^' unary)?
//   primary := number | name | name '(' sum (',' sum)* ')' | '(' sum ')'
class Parser {
 public:
  Parser(const std::string& text, int dimension) : text_(text), dimension_(dimension) {}

  Expr parse() {
    Expr e = sum();
    skip_space();
    if (pos_ < text_.size()) fail("unexpected '" + std::string(1, text_[pos_]) + "'");
    return e;
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { throw FormulaError(pos_ + 1, message); }

  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!accept(c)) fail(std::string("expected '") + c + "'");
  }

  Expr sum() {
    Expr e = product();
    for (;;) {
      if (accept('+'))
        e = e + product();
      else if (accept('-'))
        e = e - product();
      else
        return e;
    }
  }

  Expr product() {
    Expr e = unary();
    for (;;) {
      if (accept('*'))
        e = e * unary();
      else if (accept('/'))
        e = e / unary();
      else
        return e;
    }
  }

  // Every nesting (parentheses, unary signs, exponents) passes here: a
  // depth limit keeps hostile input from overflowing the stack.
  Expr unary() {
    if (++depth_ > kMaxDepth) fail("formula nested more than " + std::to_string(kMaxDepth) + " levels deep");
    Expr e = accept('-') ? -unary() : accept('+') ? unary() : power();
    --depth_;
    return e;
  }

  Expr power() {
    Expr base = primary();
    if (!accept('^')) return base;
    const std::size_t exponent_at = pos_;
    Expr exponent = unary();
    if (!exponent.is_constant()) return exp(exponent * log(base));
    const double r = exponent.constant_value();
    if (!std::isfinite(r)) {
      pos_ = exponent_at;
      fail("exponent is not a finite number");
    }
    return pow_real(base, r);
  }

  Expr primary() {
    skip_space();
    if (pos_ >= text_.size()) fail("expected a number, a variable, a function or '('");
    const char c = text_[pos_];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return number();
    if (std::isalpha(static_cast<unsigned char>(c))) return name();
    if (accept('(')) {
      Expr e = sum();
      expect(')');
      return e;
    }
    fail("expected a number, a variable, a function or '(' but found '" + std::string(1, c) + "'");
  }

  Expr number() {
    const char* begin = text_.c_str() + pos_;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin) fail("malformed number");
    if (!std::isfinite(v)) fail("number out of range");
    pos_ += static_cast<std::size_t>(end - begin);
    return v;
  }

  Expr name() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_')) ++pos_;
    const std::string id = text_.substr(start, pos_ - start);
    if (accept('(')) return call(id, start);
    if (id == "x") return Expr::x();
    if (id == "y") return Expr::y();
    if (id == "z") {
      if (dimension_ < 3) {
        pos_ = start;
        fail("'z' is not a variable of a 2D model");
      }
      return Expr::z();
    }
    if (id == "pi") return M_PI;
    if (id == "e") return M_E;
    pos_ = start;
    fail("unknown name '" + id + "' (variables are x, y, z; constants pi, e)");
  }

  Expr call(const std::string& id, std::size_t start) {
    std::vector<Expr> args{sum()};
    while (accept(',')) args.push_back(sum());
    expect(')');
    auto want = [&](std::size_t n) {
      if (args.size() != n) {
        pos_ = start;
        fail("function '" + id + "' takes " + std::to_string(n) + " argument" + (n == 1 ? "" : "s"));
      }
    };
    if (id == "sqrt") return want(1), sqrt(args[0]);
    if (id == "exp") return want(1), exp(args[0]);
    if (id == "log") return want(1), log(args[0]);
    if (id == "sin") return want(1), sin(args[0]);
    if (id == "cos") return want(1), cos(args[0]);
    if (id == "abs") return want(1), abs(args[0]);
    if (id == "min") return want(2), min(args[0], args[1]);
    if (id == "max") return want(2), max(args[0], args[1]);
    if (id == "pow") {
      want(2);
      if (args[1].is_constant()) return pow_real(args[0], args[1].constant_value());
      return exp(args[1] * log(args[0]));
    }
    pos_ = start;
    fail("unknown function '" + id + "' (known: sqrt exp log sin cos abs min max pow)");
  }

  static constexpr int kMaxDepth = 1000;
  const std::string& text_;
  int dimension_;
  std::size_t pos_ = 0;
  int depth_ = 0;
};

}  // namespace

Expr parse_formula(const std::string& text, int dimension) { return Parser(text, dimension).parse(); }

}  // namespace sage
