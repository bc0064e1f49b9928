#include <sage/scalars/rfunction.hpp>

#include <cmath>
#include <sstream>

namespace sage {

namespace {
double parse_parameter(const std::string& text, const std::string& value) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != value.size() || value.empty() || !std::isfinite(v))
    throw std::invalid_argument("R-function '" + text + "': parameter '" + value + "' is not a finite number");
  return v;
}

int even_parameter(const std::string& text, const std::string& value, int minimum) {
  const double v = parse_parameter(text, value);
  if (v < minimum || v > kMaxEvenParameter || v != std::floor(v) || static_cast<int>(v) % 2 != 0)
    throw std::invalid_argument("R-function '" + text + "': parameter must be an even integer from " +
                                std::to_string(minimum) + " to " + std::to_string(kMaxEvenParameter));
  return static_cast<int>(v);
}
}  // namespace

RSystem RSystem::r_alpha(double alpha) {
  if (!(alpha > -1.0 && alpha <= 1.0)) throw std::invalid_argument("R_alpha needs -1 < alpha <= 1");
  return {RKind::RAlpha, alpha};
}

RSystem RSystem::r_p(int p) {
  if (p < 2 || p % 2 != 0 || p > kMaxEvenParameter) throw std::invalid_argument("R_p needs an even p from 2 to 16");
  return {RKind::Rp, static_cast<double>(p)};
}

RSystem RSystem::r_m(int m) {
  if (m < 0 || m % 2 != 0 || m > kMaxEvenParameter) throw std::invalid_argument("R0^m needs an even m from 0 to 16");
  return {RKind::Rm, static_cast<double>(m)};
}

RSystem RSystem::parse(const std::string& text) {
  const auto colon = text.find(':');
  const std::string head = text.substr(0, colon);
  const std::string value = colon == std::string::npos ? "" : text.substr(colon + 1);
  const bool has_value = colon != std::string::npos;
  if (head == "minmax" && !has_value) return min_max();
  if (head == "r0" && !has_value) return r0();
  if (head == "ralpha" && has_value) {
    if (value == "var") return r_alpha_variable();
    const double a = parse_parameter(text, value);
    if (!(a > -1.0 && a <= 1.0))
      throw std::invalid_argument("R-function '" + text + "': alpha must satisfy -1 < alpha <= 1");
    return r_alpha(a);
  }
  if (head == "rp" && has_value) return r_p(even_parameter(text, value, 2));
  if (head == "rm" && has_value) return r_m(even_parameter(text, value, 2));
  throw std::invalid_argument("unknown R-function '" + text +
                              "' (expected minmax, r0, ralpha:A, ralpha:var, rp:P or rm:M with P, M even)");
}

std::string RSystem::name() const {
  std::ostringstream out;
  switch (kind) {
    case RKind::MinMax: return "minmax";
    case RKind::R0: return "r0";
    case RKind::RAlpha: out << "ralpha:" << parameter; return out.str();
    case RKind::RAlphaVariable: return "ralpha:var";
    case RKind::Rp: out << "rp:" << static_cast<int>(parameter); return out.str();
    case RKind::Rm: out << "rm:" << static_cast<int>(parameter); return out.str();
  }
  return "?";
}

}  // namespace sage
