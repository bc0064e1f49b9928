#pragma once
// A problem's data that fail at a point where the solver reads them: a
// formula that is not finite there (1/0, log(0), sqrt(-1)), a conductivity
// that is not positive, a Robin coefficient that is negative. The solvers
// check every datum at the quadrature points before they assemble, so that
// bad data end in this error instead of a crash, a solver spinning on NaN,
// or a solution of a problem that is not the one posed.

#include <array>
#include <optional>
#include <stdexcept>
#include <string>

namespace sage::solver {

class DataError : public std::invalid_argument {
 public:
  /// `datum` names the datum as a problem file does, by its JSON pointer
  /// ("/conductivity", "/boundary/load_hole/traction/0"): the structs of
  /// problem.hpp and elasticity.hpp mirror the file's schema (README.md).
  /// `requirement` says what it must be. No point: a constant, wrong everywhere.
  DataError(std::string datum, double value, const std::optional<std::array<double, 3>>& point, int dimension,
            const std::string& requirement);

  const std::string& datum() const { return datum_; }
  double value() const { return value_; }
  const std::optional<std::array<double, 3>>& point() const { return point_; }

 private:
  std::string datum_;
  double value_;
  std::optional<std::array<double, 3>> point_;
};

/// The largest magnitude of a datum: beyond it the assembly's products
/// (data times data, B-splines and weights) overflow double precision.
constexpr double kLargestDatum = 1e100;
/// The smallest conductivity (and Young's modulus): below it the stiffness
/// underflows.
constexpr double kSmallestModulus = 1e-100;
/// The largest Robin coefficient relative to the conductivity, beta h / k:
/// beyond it the condition is a Dirichlet condition to rounding, and the
/// system's condition number exceeds what double precision resolves.
constexpr double kLargestBiotNumber = 1e10;

/// A part name as one token of a JSON pointer (RFC 6901: "~" as "~0", "/" as "~1").
std::string pointer_token(const std::string& name);

}  // namespace sage::solver
