#pragma once
// ChebyshevPatch: a polynomial that stands in for an analytic field over a
// box, the building block of far-field approximation (tape_specialization.hpp).
//
// In local coordinates u_a = (x_a - centre_a) / half_a, which map the box
// onto [-1, 1]^dim, the patch is a Chebyshev series of total degree d,
//
//     p(x) = sum_{|alpha| <= d} c_alpha T_alpha1(u_1) T_alpha2(u_2) T_alpha3(u_3),
//
// fitted by interpolation at the (n + 1)^dim tensor Chebyshev points of the
// first kind (n the sampling degree, d <= n - 2). Why Chebyshev: for a
// function analytic around the box the coefficients decay geometrically,
// interpolation at these points is within a small factor of the best
// polynomial, and the coefficients beyond d measure the error: the fit is
// accepted only when they sum to at most the tolerance. That sum is an
// estimate, not a proof (a function could hide structure between the
// points); callers check analyticity over an enlarged box first, and the
// benchmarks measure the deviation from exact evaluation.
//
// Worked example (1D, n = 2): f(x) = x^2 on [-1, 1] is sampled at
// u = cos(pi/6), 0, -cos(pi/6) and gives c = {1/2, 0, 1/2}: x^2 = (T0 + T2)/2.
//
// Evaluation is generic over the scalar type: doubles and tuples through the
// three-term recurrence T_{k+1} = 2 u T_k - T_{k-1} (so tuples carry the
// patch's exact derivatives), intervals through T_k(U) = cos(k acos U),
// whose range over a sub-interval of [-1, 1] is exact. Intervals enclose the
// polynomial, not the field it replaces.
//
// Ownership: patches are immutable and shared by the tapes that use them.

#include <sage/scalars/interval.hpp>
#include <sage/scalars/tuple_lanes.hpp>

#include <array>
#include <memory>
#include <type_traits>
#include <vector>

namespace sage {

template <int N, int K>
class Tuple;

namespace detail {
template <class T>
struct IsFirstOrderTuple : std::false_type {};
template <int N>
struct IsFirstOrderTuple<Tuple<N, 1>> : std::true_type {};
}  // namespace detail

class ChebyshevPatch : public std::enable_shared_from_this<ChebyshevPatch> {
 public:
  /// The sampling point for tensor node index k (k_0 fastest) of a box:
  /// the Chebyshev points of the first kind, cos(pi (k_a + 1/2) / (n + 1)),
  /// mapped onto each axis; box has `dimension` intervals.
  static std::array<double, 3> sample_point(const Interval* box, int dimension, int n, std::size_t k);

  /// Fits the values f at the (n + 1)^dimension sample points (sample_point
  /// order), 3 <= n <= 16. Returns nothing when no total degree d <= n - 2
  /// leaves a tail of at most `tolerance`, when a sample is not finite, or
  /// when the box is flat along an axis.
  static std::shared_ptr<const ChebyshevPatch> fit(const Interval* box, int dimension, int n,
                                                   const std::vector<double>& f, double tolerance);

  int dimension() const { return dimension_; }
  int degree() const { return degree_; }
  /// The sum of |c_alpha| left out (the error estimate of the fit).
  double tail() const { return tail_; }

  /// The polynomial at the point whose coordinates are vars[0..dimension-1].
  template <class T>
  T evaluate(const T* vars) const;

  /// The polynomial at the tensor points xs[0..nx) x rows[0..row_count):
  /// point p = r * nx + i lies at (xs[i], rows[r][0], rows[r][1]), and
  /// out[p] is evaluate() there, the same numbers bit for bit (the same
  /// operations in the same order). Grid blocks and fit samples are such
  /// grids: the factors in y and z are summed once per row and the basis in
  /// x once for all rows, about five times less work than point by point.
  void evaluate_rows(const double* xs, std::size_t nx, const std::array<double, 2>* rows, std::size_t row_count,
                     double* out) const;
  /// The same in first-order tuples stored by component (BatchEvaluator's
  /// registers): vars[a].load(p) is variable a at point p, which carries
  /// the gradient through as in evaluate(). out may share lanes with vars.
  template <int N>
  void evaluate_rows(const double* xs, std::size_t nx, const std::array<double, 2>* rows, std::size_t row_count,
                     const ConstTupleLanes<Tuple<N, 1>>* vars, TupleLanes<Tuple<N, 1>> out) const;

  /// The polynomial at `count` scattered points, a point per lane: point l
  /// lies at (coordinates[0][l], coordinates[1][l], coordinates[2][l]) (the
  /// axes the patch has), and out[l] is evaluate() there, bit for bit. The
  /// sums over y and z run a lane per point as evaluate_rows' rows do: about
  /// three times less work than point by point at scattered points.
  void evaluate_points(const double* const* coordinates, std::size_t count, double* out) const;
  /// The same in first-order tuples stored by component: the coordinates
  /// are the variables' values, vars[a].component(0).
  template <int N>
  void evaluate_points(std::size_t count, const ConstTupleLanes<Tuple<N, 1>>* vars, TupleLanes<Tuple<N, 1>> out) const;

 private:
  ChebyshevPatch() = default;

  // Value and gradient (first-order tuples, what grid sampling asks for):
  // the series and its partials in doubles, by the recurrence of T_k', then
  // the chain rule to the tuple's variables; the value as evaluate<double>.
  // Defined for Tuple<1..3, 1>.
  template <class T>
  T evaluate_first_order(const T* vars) const;

  // Both evaluate_rows(): T is double (Vars, Out: nullptr_t, double*) or a
  // first-order tuple (tuple lanes).
  template <class T, class Vars, class Out>
  void rows_into(const double* xs, std::size_t nx, const std::array<double, 2>* rows, std::size_t row_count, Vars vars,
                 Out out) const;

  // Both evaluate_points().
  template <class T, class Vars, class Out>
  void points_into(const double* const* coordinates, std::size_t count, Vars vars, Out out) const;

  // The sums over the y and z degrees at one (y, z), for each x degree.
  struct RowFactors;
  RowFactors row_factors(const std::array<double, 2>& row) const;
  // row_factors() of rows[0..count), count <= 64, a row per lane.
  struct RowFactorLanes;
  void row_factor_lanes(const std::array<double, 2>* rows, std::size_t count, RowFactorLanes& f) const;

  // The tuple of `value` whose partials in the local coordinates are
  // `partial`, through the chain rule to the variables at[a].
  template <class T>
  T chain_rule(double value, const double* partial, const T* const* at) const;

  int dimension_ = 2;
  int degree_ = 0;
  std::array<double, 3> centre_{0, 0, 0};
  std::array<double, 3> inverse_half_{0, 0, 0};  // 0 along flat axes (one sample point)
  // c_alpha for |alpha| <= degree, ordered by alpha_1, then alpha_2, then alpha_3.
  std::vector<double> coefficients_;
  double tail_ = 0;
};

namespace detail {

/// T_0..T_d at u by the recurrence (doubles, tuples).
template <class T>
void chebyshev_basis(const T& u, int d, T* t) {
  t[0] = T(1.0);
  if (d >= 1) t[1] = u;
  for (int k = 2; k <= d; ++k) t[k] = 2.0 * u * t[k - 1] - t[k - 2];
}

/// Exact ranges of T_0..T_d over U (clamped to [-1, 1]).
void chebyshev_basis(const Interval& u, int d, Interval* t);

}  // namespace detail

template <class T>
T ChebyshevPatch::evaluate(const T* vars) const {
  if constexpr (detail::IsFirstOrderTuple<T>::value) return evaluate_first_order(vars);
  constexpr int kMaxDegree = 16;  // fit() refuses larger sampling degrees
  T basis[3][kMaxDegree + 1];
  const int d = degree_;
  for (int a = 0; a < dimension_; ++a) detail::chebyshev_basis((vars[a] - centre_[a]) * inverse_half_[a], d, basis[a]);
  const double* c = coefficients_.data();
  T sum(0.0);
  if (dimension_ == 1) {
    for (int i = 0; i <= d; ++i) sum = sum + *c++ * basis[0][i];
  } else if (dimension_ == 2) {
    for (int i = 0; i <= d; ++i) {
      T inner(0.0);
      for (int j = 0; j <= d - i; ++j) inner = inner + *c++ * basis[1][j];
      sum = sum + inner * basis[0][i];
    }
  } else {
    for (int i = 0; i <= d; ++i) {
      T middle(0.0);
      for (int j = 0; j <= d - i; ++j) {
        T inner(0.0);
        for (int k = 0; k <= d - i - j; ++k) inner = inner + *c++ * basis[2][k];
        middle = middle + inner * basis[1][j];
      }
      sum = sum + middle * basis[0][i];
    }
  }
  return sum;
}

}  // namespace sage
