#include <sage/scalars/tuple.hpp>
#include <sage/tape/chebyshev_patch.hpp>

#include "../scalars/vector_clones.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

namespace sage {

std::array<double, 3> ChebyshevPatch::sample_point(const Interval* box, int dimension, int n, std::size_t k) {
  std::array<double, 3> p{0, 0, 0};
  const std::size_t m = static_cast<std::size_t>(n + 1);
  for (int a = 0; a < dimension; ++a, k /= m) {
    const double u = std::cos(std::numbers::pi * (static_cast<double>(k % m) + 0.5) / (n + 1));
    p[a] = box[a].mid() + u * 0.5 * box[a].width();
  }
  return p;
}

namespace {

constexpr int kMaxDegree = 16;        // fit() refuses larger sampling degrees
constexpr std::size_t kLanes = 64;    // points of a row, or rows, per pass
constexpr std::size_t kBlock = 8;     // points whose sums over x degrees stay in registers
constexpr std::size_t kRowBlock = 4;  // rows whose sums over y degrees stay in registers

/// Whether the samples on some line of nodes, along any axis, have a 1D
/// interpolant with |b_{n-1}| + |b_n| > tolerance: then the fit must fail,
/// and this costs about a sixth of a 2D fit (far-field approximation
/// tries many fits that fail). Why: along axis a, b_i is the sum over the
/// other indices of c_alpha times T at their nodes, and |T| <= 1, so for
/// every d <= n - 2, |b_{n-1}| + |b_n| <= sum_{alpha_a > d} |c_alpha| <=
/// the tail of total degree d. The margin covers both sums' rounding.
/// t[i * m + k] is T_i at node k.
bool lines_exceed_tail(const std::vector<double>& f, int dimension, int n, const std::vector<double>& t,
                       double tolerance) {
  const std::size_t m = static_cast<std::size_t>(n + 1), total = f.size();
  double largest = 0;
  for (double v : f) largest = std::max(largest, std::abs(v));
  const double margin = 16.0 * static_cast<double>(total * m) * std::numeric_limits<double>::epsilon() * largest;
  const double* high = &t[static_cast<std::size_t>(n - 1) * m];  // T_{n-1}, then T_n, at the nodes
  std::size_t stride = 1;
  for (int a = 0; a < dimension; ++a, stride *= m)
    for (std::size_t outer = 0; outer < total; outer += stride * m)
      for (std::size_t inner = 0; inner < stride; ++inner) {
        const double* line = &f[outer + inner];
        double s1 = 0, s2 = 0;
        for (std::size_t k = 0; k < m; ++k) {
          s1 += line[k * stride] * high[k];
          s2 += line[k * stride] * high[m + k];
        }
        if ((std::abs(s1) + std::abs(s2)) * 2.0 / static_cast<double>(m) > tolerance + margin) return true;
      }
  return false;
}

/// The discrete Chebyshev transform of c along each axis in turn (a line:
/// the m values whose indices differ in axis a only), c_i = (i ? 2 : 1) /
/// m * sum_k c_k T_i(node k), each sum in the order of k; next is scratch
/// of c's size. The sums of an axis run side by side, a vector lane each
/// (along axis 0, whose lines are contiguous, the m sums of one line), so
/// that no addition waits on the one before. t as in lines_exceed_tail(),
/// then its transpose.
///
/// Fits need every coefficient only when they succeed, and most fail
/// (far-field approximation tries the subtrees below a failed fit): the
/// last axis (in 2D and 3D) runs its degrees from the highest down, and the
/// transform stops, returning false, as soon as the coefficients of total
/// degree n - 1 and above found so far sum to more than `tolerance`, the tail
/// that every patch of degree <= n - 2 leaves. Each coefficient's sum is
/// the same either way.
bool chebyshev_transform(int dimension, std::size_t m, const std::vector<double>& t, std::vector<double>& c,
                         std::vector<double>& next, double tolerance) {
  double acc[(kMaxDegree + 1) * (kMaxDegree + 1)];
  const double* transposed = &t[m * m];
  const std::size_t total = c.size();
  const std::size_t high = m - 2;  // total degrees n - 1 = m - 2 and above are in every tail
  std::size_t stride = 1;
  for (int a = 0; a < dimension; ++a, stride *= m) {
    const bool last = a == dimension - 1 && dimension > 1;
    double tail = 0;
    for (std::size_t outer = 0; outer < total; outer += stride * m) {
      if (stride == 1) {
        for (std::size_t i = 0; i < m; ++i) acc[i] = 0;
        for (std::size_t k = 0; k < m; ++k) {
          const double ck = c[outer + k];
          for (std::size_t i = 0; i < m; ++i) acc[i] += ck * transposed[k * m + i];
        }
        for (std::size_t i = 0; i < m; ++i) next[outer + i] = acc[i] * (i == 0 ? 1.0 : 2.0) / static_cast<double>(m);
        continue;
      }
      for (std::size_t step = 0; step < m; ++step) {
        const std::size_t i = last ? m - 1 - step : step;
        for (std::size_t inner = 0; inner < stride; ++inner) acc[inner] = 0;
        for (std::size_t k = 0; k < m; ++k) {
          const double tik = t[i * m + k];
          const double* line = &c[outer + k * stride];
          for (std::size_t inner = 0; inner < stride; ++inner) acc[inner] += line[inner] * tik;
        }
        for (std::size_t inner = 0; inner < stride; ++inner)
          next[outer + i * stride + inner] = acc[inner] * (i == 0 ? 1.0 : 2.0) / static_cast<double>(m);
        if (!last) continue;
        for (std::size_t inner = 0; inner < stride; ++inner) {
          const std::size_t degree = i + inner % m + inner / m;  // inner < m^2: its two degrees
          if (degree >= high) tail += std::abs(next[outer + i * stride + inner]);
        }
        // A hair above the tolerance: fit() decides the borderline cases
        // from all coefficients.
        if (tail > tolerance * (1 + 1e-9)) return false;
      }
    }
    std::swap(c, next);
  }
  return true;
}

}  // namespace

std::shared_ptr<const ChebyshevPatch> ChebyshevPatch::fit(const Interval* box, int dimension, int n,
                                                          const std::vector<double>& f, double tolerance) {
  if (n < 3 || n > kMaxDegree || dimension < 1 || dimension > 3) return nullptr;
  const std::size_t m = static_cast<std::size_t>(n + 1);
  std::size_t total = 1;
  for (int a = 0; a < dimension; ++a) total *= m;
  if (f.size() != total) return nullptr;
  for (double v : f)
    if (!std::isfinite(v)) return nullptr;
  for (int a = 0; a < dimension; ++a)
    if (!(box[a].width() > 0)) return nullptr;

  // cos(i pi (k + 1/2) / (n + 1)): T_i at node k. Far-field approximation
  // fits thousands of patches of one sampling degree: keep the table.
  thread_local std::vector<double> t;
  thread_local std::size_t t_size = 0;
  if (t_size != m) {
    t.resize(2 * m * m);  // then the transpose, T_i at node k in t[m * m + k * m + i]
    for (std::size_t i = 0; i < m; ++i)
      for (std::size_t k = 0; k < m; ++k)
        t[i * m + k] = t[m * m + k * m + i] = std::cos(std::numbers::pi * static_cast<double>(i) *
                                                       (static_cast<double>(k) + 0.5) / static_cast<double>(m));
    t_size = m;
  }

  if (lines_exceed_tail(f, dimension, n, t, tolerance)) return nullptr;

  thread_local std::vector<double> c, next;
  c.assign(f.begin(), f.end());
  next.resize(total);
  if (!chebyshev_transform(dimension, m, t, c, next, tolerance)) return nullptr;

  // Sum of |c| by total degree, then the smallest degree whose tail fits.
  auto degrees = [&](std::size_t index) {
    std::array<int, 3> alpha{0, 0, 0};
    for (int a = 0; a < dimension; ++a, index /= m) alpha[a] = static_cast<int>(index % m);
    return alpha;
  };
  std::array<double, 3 * kMaxDegree + 1> by_degree{};  // up to total degree dimension * n
  for (std::size_t index = 0; index < total; ++index) {
    const auto alpha = degrees(index);
    by_degree[static_cast<std::size_t>(alpha[0] + alpha[1] + alpha[2])] += std::abs(c[index]);
  }
  double tail = 0;
  for (double s : by_degree) tail += s;
  int d = -1;
  for (int candidate = 0; candidate <= n - 2; ++candidate) {
    tail -= by_degree[static_cast<std::size_t>(candidate)];
    if (tail <= tolerance) {
      d = candidate;
      break;
    }
  }
  if (d < 0) return nullptr;

  std::shared_ptr<ChebyshevPatch> patch(new ChebyshevPatch());
  patch->dimension_ = dimension;
  patch->degree_ = d;
  patch->tail_ = std::max(tail, 0.0);
  for (int a = 0; a < dimension; ++a) {
    patch->centre_[a] = box[a].mid();
    patch->inverse_half_[a] = 2.0 / box[a].width();
  }
  // Keep |alpha| <= d in the evaluation order of evaluate().
  auto at = [&](int i, int j, int k) {
    return c[static_cast<std::size_t>(i) + m * (static_cast<std::size_t>(j) + m * static_cast<std::size_t>(k))];
  };
  for (int i = 0; i <= d; ++i) {
    if (dimension == 1) {
      patch->coefficients_.push_back(at(i, 0, 0));
      continue;
    }
    for (int j = 0; j <= d - i; ++j) {
      if (dimension == 2) {
        patch->coefficients_.push_back(at(i, j, 0));
        continue;
      }
      for (int k = 0; k <= d - i - j; ++k) patch->coefficients_.push_back(at(i, j, k));
    }
  }
  return patch;
}

namespace {

/// T_0..T_d and their derivatives at u, by T_k' = 2 T_{k-1} + 2 u T_{k-1}' - T_{k-2}'.
void basis_with_derivative(double u, int d, double* t, double* dt) {
  t[0] = 1.0;
  dt[0] = 0.0;
  if (d >= 1) t[1] = u, dt[1] = 1.0;
  for (int k = 2; k <= d; ++k) {
    t[k] = 2.0 * u * t[k - 1] - t[k - 2];
    dt[k] = 2.0 * t[k - 1] + 2.0 * u * dt[k - 1] - dt[k - 2];
  }
}

/// basis_with_derivative() at u[0..n), a lane each: T_k(u[l]) in t[k][l].
[[gnu::always_inline]] inline void basis_lanes(const double* u, std::size_t n, int d, double (*t)[kLanes],
                                               double (*dt)[kLanes]) {
  for (std::size_t l = 0; l < n; ++l) {
    t[0][l] = 1.0;
    dt[0][l] = 0.0;
    if (d >= 1) t[1][l] = u[l], dt[1][l] = 1.0;
  }
  for (int k = 2; k <= d; ++k)
    for (std::size_t l = 0; l < n; ++l) {
      t[k][l] = 2.0 * u[l] * t[k - 1][l] - t[k - 2][l];
      dt[k][l] = 2.0 * t[k - 1][l] + 2.0 * u[l] * dt[k - 1][l] - dt[k - 2][l];
    }
}

}  // namespace

/// For each x degree i, the sum over the other degrees at one (y, z),
/// e[i], and its derivatives in v = u_y, ev[i], and w = u_z, ew[i] (zero
/// along axes the patch does not have).
struct ChebyshevPatch::RowFactors {
  double e[kMaxDegree + 1], ev[kMaxDegree + 1], ew[kMaxDegree + 1];
};

ChebyshevPatch::RowFactors ChebyshevPatch::row_factors(const std::array<double, 2>& row) const {
  const int d = degree_;
  RowFactors f;
  const double* c = coefficients_.data();
  if (dimension_ == 1) {
    for (int i = 0; i <= d; ++i) f.e[i] = c[i], f.ev[i] = f.ew[i] = 0.0;
    return f;
  }
  double t1[kMaxDegree + 1], dt1[kMaxDegree + 1], t2[kMaxDegree + 1], dt2[kMaxDegree + 1];
  basis_with_derivative((row[0] - centre_[1]) * inverse_half_[1], d, t1, dt1);
  if (dimension_ == 2) {
    for (int i = 0; i <= d; ++i) {
      double inner = 0.0, inner_v = 0.0;
      for (int j = 0; j <= d - i; ++j, ++c) {
        inner = inner + *c * t1[j];
        inner_v += *c * dt1[j];
      }
      f.e[i] = inner, f.ev[i] = inner_v, f.ew[i] = 0.0;
    }
    return f;
  }
  basis_with_derivative((row[1] - centre_[2]) * inverse_half_[2], d, t2, dt2);
  for (int i = 0; i <= d; ++i) {
    double middle = 0.0, middle_v = 0.0, middle_w = 0.0;
    for (int j = 0; j <= d - i; ++j) {
      double inner = 0.0, inner_w = 0.0;
      for (int k = 0; k <= d - i - j; ++k, ++c) {
        inner = inner + *c * t2[k];
        inner_w += *c * dt2[k];
      }
      middle = middle + inner * t1[j];
      middle_v += inner * dt1[j];
      middle_w += inner_w * t1[j];
    }
    f.e[i] = middle, f.ev[i] = middle_v, f.ew[i] = middle_w;
  }
  return f;
}

struct ChebyshevPatch::RowFactorLanes {
  double e[kMaxDegree + 1][kLanes], ev[kMaxDegree + 1][kLanes], ew[kMaxDegree + 1][kLanes];
};

SAGE_VECTOR_CLONES void ChebyshevPatch::row_factor_lanes(const std::array<double, 2>* rows, std::size_t count,
                                                         RowFactorLanes& f) const {
  const int d = degree_;
  const double* c = coefficients_.data();
  if (dimension_ == 1) {
    for (int i = 0; i <= d; ++i)
      for (std::size_t r = 0; r < count; ++r) f.e[i][r] = c[i], f.ev[i][r] = f.ew[i][r] = 0.0;
    return;
  }
  // Rows past count, up to a whole block, at the centre: computed, never read.
  const std::size_t padded = (count + kRowBlock - 1) / kRowBlock * kRowBlock;
  double u[kLanes] = {}, t1[kMaxDegree + 1][kLanes], dt1[kMaxDegree + 1][kLanes];
  for (std::size_t r = 0; r < padded; ++r) u[r] = r < count ? (rows[r][0] - centre_[1]) * inverse_half_[1] : 0.0;
  basis_lanes(u, padded, d, t1, dt1);
  if (dimension_ == 2) {
    // row_factors()' sums, kRowBlock rows at a time so that they stay in
    // registers: independent sums instead of one chain of additions.
    for (std::size_t first = 0; first < padded; first += kRowBlock) {
      const double* ci = c;
      for (int i = 0; i <= d; ++i) {
        double inner[kRowBlock] = {}, inner_v[kRowBlock] = {};
        for (int j = 0; j <= d - i; ++j, ++ci)
          for (std::size_t q = 0; q < kRowBlock; ++q) {
            inner[q] = inner[q] + *ci * t1[j][first + q];
            inner_v[q] += *ci * dt1[j][first + q];
          }
        for (std::size_t q = 0; q < kRowBlock; ++q)
          f.e[i][first + q] = inner[q], f.ev[i][first + q] = inner_v[q], f.ew[i][first + q] = 0.0;
      }
    }
    return;
  }
  double t2[kMaxDegree + 1][kLanes], dt2[kMaxDegree + 1][kLanes];
  for (std::size_t r = 0; r < padded; ++r) u[r] = r < count ? (rows[r][1] - centre_[2]) * inverse_half_[2] : 0.0;
  basis_lanes(u, padded, d, t2, dt2);
  for (int i = 0; i <= d; ++i) {
    double middle[kLanes] = {}, middle_v[kLanes] = {}, middle_w[kLanes] = {};
    for (int j = 0; j <= d - i; ++j) {
      double inner[kLanes] = {}, inner_w[kLanes] = {};
      for (int k = 0; k <= d - i - j; ++k, ++c)
        for (std::size_t r = 0; r < count; ++r) {
          inner[r] = inner[r] + *c * t2[k][r];
          inner_w[r] += *c * dt2[k][r];
        }
      for (std::size_t r = 0; r < count; ++r) {
        middle[r] = middle[r] + inner[r] * t1[j][r];
        middle_v[r] += inner[r] * dt1[j][r];
        middle_w[r] += inner_w[r] * t1[j][r];
      }
    }
    for (std::size_t r = 0; r < count; ++r) f.e[i][r] = middle[r], f.ev[i][r] = middle_v[r], f.ew[i][r] = middle_w[r];
  }
}

template <class T>
T ChebyshevPatch::chain_rule(double value, const double* partial, const T* const* at) const {
  T r(value);
  for (int a = 0; a < dimension_; ++a) {
    const double scale = partial[a] * inverse_half_[a];
    for (std::size_t q = 1; q < r.c.size(); ++q) r.c[q] += scale * at[a]->c[q];
  }
  return r;
}

template <class T>
T ChebyshevPatch::evaluate_first_order(const T* vars) const {
  const RowFactors f = row_factors({dimension_ > 1 ? vars[1].value() : 0.0, dimension_ > 2 ? vars[2].value() : 0.0});
  double t[kMaxDegree + 1], dt[kMaxDegree + 1];
  basis_with_derivative((vars[0].value() - centre_[0]) * inverse_half_[0], degree_, t, dt);
  double sum = 0.0, partial[3] = {0.0, 0.0, 0.0};  // d/du_a
  for (int i = 0; i <= degree_; ++i) {
    sum = sum + f.e[i] * t[i];
    partial[0] += f.e[i] * dt[i];
    partial[1] += f.ev[i] * t[i];
    partial[2] += f.ew[i] * t[i];
  }
  const T* at[3] = {&vars[0], &vars[std::min(1, dimension_ - 1)], &vars[std::min(2, dimension_ - 1)]};
  return chain_rule(sum, partial, at);
}

template <class T, class Vars, class Out>
SAGE_VECTOR_CLONES void ChebyshevPatch::rows_into(const double* xs, std::size_t nx, const std::array<double, 2>* rows,
                                                  std::size_t row_count, Vars vars, Out out) const {
  constexpr bool kGradient = !std::is_same_v<T, double>;
  const int d = degree_;
  double t0[kMaxDegree + 1][kLanes], dt0[kMaxDegree + 1][kLanes];
  double sum[kLanes], p0[kLanes], p1[kLanes], p2[kLanes];
  RowFactorLanes f;
  // The sums over the x degrees at row r, with the partials along `axes`
  // axes (the others stay zero): evaluate_first_order's loop, a lane per
  // point, kBlock lanes at a time so that the sums stay in registers.
  auto sum_lanes = [&]<int axes>(std::size_t r, std::size_t n) {
    for (std::size_t first = 0; first < n; first += kBlock) {
      double s[kBlock] = {}, a[kBlock] = {}, b[kBlock] = {}, c[kBlock] = {};
      for (int i = 0; i <= d; ++i) {
        const double e = f.e[i][r], ev = f.ev[i][r], ew = f.ew[i][r];
        const double* t = &t0[i][first];
        const double* dt = &dt0[i][first];
        for (std::size_t q = 0; q < kBlock; ++q) {
          s[q] = s[q] + e * t[q];
          if constexpr (axes >= 1) a[q] += e * dt[q];
          if constexpr (axes >= 2) b[q] += ev * t[q];
          if constexpr (axes >= 3) c[q] += ew * t[q];
        }
      }
      for (std::size_t q = 0; q < kBlock; ++q)
        sum[first + q] = s[q], p0[first + q] = a[q], p1[first + q] = b[q], p2[first + q] = c[q];
    }
  };
  // chain_rule() a component at a time: each gradient component is 0 +
  // the sum over the `axes` axes of partial * inverse_half * the variable's
  // component, in the order of the axes; then the value. Each lane reads
  // its variables before it writes, and out is a variable or none of them.
  auto chain_lanes = [&]<int axes>(std::size_t base, std::size_t n) {
    if constexpr (kGradient) {
      const double* partial[3] = {p0, p1, p2};
      for (int q = 1; q < T::size; ++q) {
        const double* v[axes];
        for (int a = 0; a < axes; ++a) v[a] = vars[a].component(q) + base;
        double* o = out.component(q) + base;
#pragma GCC ivdep
        for (std::size_t l = 0; l < n; ++l) {
          double acc = 0.0;
          for (int a = 0; a < axes; ++a) acc += partial[a][l] * inverse_half_[a] * v[a][l];
          o[l] = acc;
        }
      }
      double* o = out.component(0) + base;
#pragma GCC ivdep
      for (std::size_t l = 0; l < n; ++l) o[l] = sum[l];
    }
  };
  for (std::size_t first_row = 0; first_row < row_count; first_row += kLanes) {
    const std::size_t rows_now = std::min(kLanes, row_count - first_row);
    row_factor_lanes(rows + first_row, rows_now, f);
    for (std::size_t first = 0; first < nx; first += kLanes) {
      const std::size_t n = std::min(kLanes, nx - first);
      // The basis in x, shared by every row (lanes past n, up to a whole
      // block, at u = 0, computed and never stored).
      double u[kLanes];
      const std::size_t padded = (n + kBlock - 1) / kBlock * kBlock;
      for (std::size_t l = 0; l < padded; ++l) u[l] = l < n ? (xs[first + l] - centre_[0]) * inverse_half_[0] : 0.0;
      basis_lanes(u, padded, d, t0, dt0);
      for (std::size_t r = 0; r < rows_now; ++r) {
        if (!kGradient)
          sum_lanes.template operator()<0>(r, n);
        else if (dimension_ == 1)
          sum_lanes.template operator()<1>(r, n);
        else if (dimension_ == 2)
          sum_lanes.template operator()<2>(r, n);
        else
          sum_lanes.template operator()<3>(r, n);
        const std::size_t base = (first_row + r) * nx + first;
        if constexpr (kGradient) {
          if (dimension_ == 1)
            chain_lanes.template operator()<1>(base, n);
          else if (dimension_ == 2)
            chain_lanes.template operator()<2>(base, n);
          else
            chain_lanes.template operator()<3>(base, n);
        } else {
          for (std::size_t l = 0; l < n; ++l) out[base + l] = sum[l];
        }
      }
    }
  }
}

template <class T, class Vars, class Out>
SAGE_VECTOR_CLONES void ChebyshevPatch::points_into(const double* const* coordinates, std::size_t count, Vars vars,
                                                    Out out) const {
  constexpr bool kGradient = !std::is_same_v<T, double>;
  const int d = degree_;
  double t0[kMaxDegree + 1][kLanes], dt0[kMaxDegree + 1][kLanes];
  double sum[kLanes], partial[3][kLanes];
  RowFactorLanes f;
  std::array<double, 2> rows[kLanes];
  // evaluate_first_order()'s sums over the x degrees, in its order, a lane
  // per point, with the partials along `axes` axes; kBlock lanes at a time
  // so that the sums stay in registers.
  auto sum_lanes = [&]<int axes>(std::size_t n) {
    for (std::size_t first = 0; first < n; first += kBlock) {
      double s[kBlock] = {}, a[kBlock] = {}, b[kBlock] = {}, c[kBlock] = {};
      for (int i = 0; i <= d; ++i)
        for (std::size_t q = 0; q < kBlock; ++q) {
          const std::size_t l = first + q;
          s[q] = s[q] + f.e[i][l] * t0[i][l];
          if constexpr (axes >= 1) a[q] += f.e[i][l] * dt0[i][l];
          if constexpr (axes >= 2) b[q] += f.ev[i][l] * t0[i][l];
          if constexpr (axes >= 3) c[q] += f.ew[i][l] * t0[i][l];
        }
      for (std::size_t q = 0; q < kBlock; ++q)
        sum[first + q] = s[q], partial[0][first + q] = a[q], partial[1][first + q] = b[q], partial[2][first + q] = c[q];
    }
  };
  for (std::size_t first = 0; first < count; first += kLanes) {
    const std::size_t n = std::min(kLanes, count - first);
    // Each point is its own row: row_factors() of its y (and z), a lane
    // each; lanes past n, up to a whole block, at the centre (computed,
    // never stored).
    const std::size_t padded = (n + kBlock - 1) / kBlock * kBlock;
    double u[kLanes];
    for (std::size_t l = 0; l < padded; ++l) {
      const bool real = l < n;
      rows[l] = {dimension_ > 1 && real ? coordinates[1][first + l] : centre_[1],
                 dimension_ > 2 && real ? coordinates[2][first + l] : centre_[2]};
      u[l] = real ? (coordinates[0][first + l] - centre_[0]) * inverse_half_[0] : 0.0;
    }
    row_factor_lanes(rows, padded, f);
    basis_lanes(u, padded, d, t0, dt0);
    if (!kGradient)
      sum_lanes.template operator()<0>(padded);
    else if (dimension_ == 1)
      sum_lanes.template operator()<1>(padded);
    else if (dimension_ == 2)
      sum_lanes.template operator()<2>(padded);
    else
      sum_lanes.template operator()<3>(padded);
    if constexpr (kGradient) {
      // chain_rule(): each gradient component is 0 + the sum over the axes
      // of partial * inverse_half * the variable's component, then the
      // value. Each lane reads its variables before it writes.
      for (int q = 1; q < T::size; ++q) {
        double* o = out.component(q) + first;
        for (std::size_t l = 0; l < n; ++l) {
          double acc = 0.0;
          for (int a = 0; a < dimension_; ++a)
            acc += partial[a][l] * inverse_half_[a] * vars[a].component(q)[first + l];
          o[l] = acc;
        }
      }
      double* o = out.component(0) + first;
      for (std::size_t l = 0; l < n; ++l) o[l] = sum[l];
    } else {
      for (std::size_t l = 0; l < n; ++l) out[first + l] = sum[l];
    }
  }
}

void ChebyshevPatch::evaluate_points(const double* const* coordinates, std::size_t count, double* out) const {
  points_into<double>(coordinates, count, nullptr, out);
}

template <int N>
void ChebyshevPatch::evaluate_points(std::size_t count, const ConstTupleLanes<Tuple<N, 1>>* vars,
                                     TupleLanes<Tuple<N, 1>> out) const {
  const double* coordinates[3] = {vars[0].component(0), vars[std::min(1, N - 1)].component(0),
                                  vars[std::min(2, N - 1)].component(0)};
  points_into<Tuple<N, 1>>(coordinates, count, vars, out);
}

template void ChebyshevPatch::evaluate_points(std::size_t, const ConstTupleLanes<Tuple<1, 1>>*,
                                              TupleLanes<Tuple<1, 1>>) const;
template void ChebyshevPatch::evaluate_points(std::size_t, const ConstTupleLanes<Tuple<2, 1>>*,
                                              TupleLanes<Tuple<2, 1>>) const;
template void ChebyshevPatch::evaluate_points(std::size_t, const ConstTupleLanes<Tuple<3, 1>>*,
                                              TupleLanes<Tuple<3, 1>>) const;

template Tuple<1, 1> ChebyshevPatch::evaluate_first_order(const Tuple<1, 1>*) const;
template Tuple<2, 1> ChebyshevPatch::evaluate_first_order(const Tuple<2, 1>*) const;
template Tuple<3, 1> ChebyshevPatch::evaluate_first_order(const Tuple<3, 1>*) const;
void ChebyshevPatch::evaluate_rows(const double* xs, std::size_t nx, const std::array<double, 2>* rows,
                                   std::size_t row_count, double* out) const {
  rows_into<double>(xs, nx, rows, row_count, nullptr, out);
}

template <int N>
void ChebyshevPatch::evaluate_rows(const double* xs, std::size_t nx, const std::array<double, 2>* rows,
                                   std::size_t row_count, const ConstTupleLanes<Tuple<N, 1>>* vars,
                                   TupleLanes<Tuple<N, 1>> out) const {
  rows_into<Tuple<N, 1>>(xs, nx, rows, row_count, vars, out);
}

template void ChebyshevPatch::evaluate_rows(const double*, std::size_t, const std::array<double, 2>*, std::size_t,
                                            const ConstTupleLanes<Tuple<1, 1>>*, TupleLanes<Tuple<1, 1>>) const;
template void ChebyshevPatch::evaluate_rows(const double*, std::size_t, const std::array<double, 2>*, std::size_t,
                                            const ConstTupleLanes<Tuple<2, 1>>*, TupleLanes<Tuple<2, 1>>) const;
template void ChebyshevPatch::evaluate_rows(const double*, std::size_t, const std::array<double, 2>*, std::size_t,
                                            const ConstTupleLanes<Tuple<3, 1>>*, TupleLanes<Tuple<3, 1>>) const;

namespace detail {

void chebyshev_basis(const Interval& u, int d, Interval* t) {
  // T_k(cos theta) = cos(k theta); acos is decreasing, and glibc's acos is
  // within an ulp or so: two ulps outward are enough.
  const double lo = std::clamp(u.lo, -1.0, 1.0), hi = std::clamp(u.hi, -1.0, 1.0);
  const Interval theta(std::max(0.0, down(std::acos(hi), 2)),
                       std::min(std::numbers::pi * (1 + 1e-15), up(std::acos(lo), 2)));
  for (int k = 0; k <= d; ++k) {
    const Interval v = k == 0 ? Interval(1.0) : cos(Interval(static_cast<double>(k)) * theta);
    t[k] = Interval(std::max(v.lo, -1.0), std::min(v.hi, 1.0));
  }
}

}  // namespace detail

}  // namespace sage
