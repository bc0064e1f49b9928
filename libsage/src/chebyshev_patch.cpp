#include <sage/chebyshev_patch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

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

std::shared_ptr<const ChebyshevPatch> ChebyshevPatch::fit(const Interval* box, int dimension, int n,
                                                          const std::vector<double>& f, double tolerance) {
  if (n < 3 || n > 16 || dimension < 1 || dimension > 3) return nullptr;
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
    t.resize(m * m);
    for (std::size_t i = 0; i < m; ++i)
      for (std::size_t k = 0; k < m; ++k)
        t[i * m + k] = std::cos(std::numbers::pi * static_cast<double>(i) * (static_cast<double>(k) + 0.5) /
                                static_cast<double>(m));
    t_size = m;
  }

  // The discrete Chebyshev transform along each axis in turn, line by line
  // (a line: the m values whose indices differ in axis a only).
  thread_local std::vector<double> c, next;
  c.assign(f.begin(), f.end());
  next.resize(total);
  std::size_t stride = 1;
  for (int a = 0; a < dimension; ++a, stride *= m) {
    for (std::size_t outer = 0; outer < total; outer += stride * m)
      for (std::size_t inner = 0; inner < stride; ++inner) {
        const std::size_t base = outer + inner;
        for (std::size_t i = 0; i < m; ++i) {
          double s = 0;
          for (std::size_t k = 0; k < m; ++k) s += c[base + k * stride] * t[i * m + k];
          next[base + i * stride] = s * (i == 0 ? 1.0 : 2.0) / static_cast<double>(m);
        }
      }
    std::swap(c, next);
  }

  // Sum of |c| by total degree, then the smallest degree whose tail fits.
  auto degrees = [&](std::size_t index) {
    std::array<int, 3> alpha{0, 0, 0};
    for (int a = 0; a < dimension; ++a, index /= m) alpha[a] = static_cast<int>(index % m);
    return alpha;
  };
  std::vector<double> by_degree(static_cast<std::size_t>(dimension * n + 1), 0.0);
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
