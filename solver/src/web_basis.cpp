#include <sage/solver/web_basis.hpp>

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

namespace sage::solver {

BasisKind parse_basis_kind(const std::string& text) {
  if (text == "web") return BasisKind::Web;
  if (text == "weighted") return BasisKind::Weighted;
  throw std::invalid_argument("basis must be web or weighted, not '" + text + "'");
}

namespace {

/// Calls visit(spline multi-index) for the (degree + 1)^D splines nonzero on cell c.
template <int D, class Visit>
void for_each_local_spline(const std::array<int, D>& c, int degree, Visit&& visit) {
  int total = 1;
  for (int a = 0; a < D; ++a) total *= degree + 1;
  for (int k = 0; k < total; ++k) {
    std::array<int, D> i{};
    int rest = k;
    for (int a = 0; a < D; ++a) {
      i[a] = c[a] + rest % (degree + 1);
      rest /= degree + 1;
    }
    visit(i);
  }
}

/// block_ok[l] = every spline l + {0..n}^D is inner, by one pass per axis.
template <int D>
std::vector<char> full_inner_blocks(const BackgroundGrid<D>& grid, const std::vector<char>& inner) {
  std::vector<char> ok = inner;
  const std::size_t n = grid.spline_count();
  for (int a = 0; a < D; ++a) {
    std::vector<char> next(n, 0);
    for (std::size_t s = 0; s < n; ++s) {
      auto i = grid.spline_index(s);
      bool all = i[a] + grid.degree < grid.splines_along(a);
      for (int mu = 0; all && mu <= grid.degree; ++mu) {
        auto j = i;
        j[a] += mu;
        all = ok[grid.spline_linear(j)] != 0;
      }
      next[s] = all ? 1 : 0;
    }
    ok.swap(next);
  }
  return ok;
}

/// Lagrange weight of node m (of 0..n) at x: prod_{mu != m} (x - mu) / (m - mu).
double lagrange_weight(int n, int m, double x) {
  double w = 1.0;
  for (int mu = 0; mu <= n; ++mu)
    if (mu != m) w *= (x - mu) / (m - mu);
  return w;
}

/// The lower corner l of the full array of inner B-splines l + {0..n}^D
/// whose centre is nearest outer spline j (Hoellig's WEB extension), from
/// growing shells of corners around j.
template <int D>
std::array<int, D> nearest_inner_array(const BackgroundGrid<D>& grid, const std::vector<char>& block_ok,
                                       const std::array<int, D>& j) {
  const int n = grid.degree;
  for (int radius = 0; radius <= 2 * (n + 1) + 64; ++radius) {
    double best_distance = std::numeric_limits<double>::infinity();
    std::optional<std::array<int, D>> best;
    std::array<int, D> lo{}, span{};
    int total = 1;
    for (int a = 0; a < D; ++a) {
      lo[a] = j[a] - n / 2 - radius;
      span[a] = 2 * radius + 1;
      total *= span[a];
    }
    for (int k = 0; k < total; ++k) {
      std::array<int, D> l{};
      int rest = k;
      bool in_range = true;
      double distance = 0.0;
      for (int a = 0; a < D; ++a) {
        l[a] = lo[a] + rest % span[a];
        rest /= span[a];
        in_range = in_range && l[a] >= 0 && l[a] + n < grid.splines_along(a);
        const double d = l[a] + 0.5 * n - j[a];
        distance += d * d;
      }
      if (!in_range || !block_ok[grid.spline_linear(l)] || distance >= best_distance) continue;
      best_distance = distance;
      best = l;
    }
    if (best) return *best;
  }
  throw std::runtime_error("the grid is too coarse for the WEB basis: an outer B-spline has no array of " +
                           std::to_string(n + 1) + "^" + std::to_string(D) +
                           " inner B-splines nearby (use more cells)");
}

}  // namespace

template <int D>
SplineBasis<D> build_basis(const BackgroundGrid<D>& grid, const std::vector<char>& active,
                           const std::vector<char>& inside, BasisKind kind) {
  SplineBasis<D> basis;
  basis.grid = grid;
  basis.kind = kind;
  const std::size_t splines = grid.spline_count();
  std::vector<char> relevant(splines, 0), inner(splines, 0);
  for (std::size_t c = 0; c < grid.cell_count(); ++c) {
    if (!active[c]) continue;
    for_each_local_spline<D>(grid.cell_index(c), grid.degree, [&](const std::array<int, D>& i) {
      const std::size_t s = grid.spline_linear(i);
      relevant[s] = 1;
      if (inside[c]) inner[s] = 1;
    });
  }
  basis.relevant_of.assign(splines, -1);
  for (std::size_t s = 0; s < splines; ++s) {
    if (!relevant[s]) continue;
    basis.relevant_of[s] = static_cast<long long>(basis.relevant.size());
    basis.relevant.push_back(s);
    if (inner[s]) {
      ++basis.inner_count;
    } else {
      ++basis.outer_count;
    }
  }
  if (basis.relevant.empty()) throw std::runtime_error("the domain (/domain) is empty: no grid cell meets it");
  const auto rows = static_cast<Eigen::Index>(basis.relevant.size());
  std::vector<Eigen::Triplet<double>> entries;
  if (kind == BasisKind::Weighted) {
    for (Eigen::Index r = 0; r < rows; ++r) {
      entries.emplace_back(r, r, 1.0);
      basis.unknown_spline.push_back(static_cast<std::size_t>(r));
    }
    basis.extension.resize(rows, rows);
    basis.extension.setFromTriplets(entries.begin(), entries.end());
    return basis;
  }
  if (basis.inner_count == 0)
    throw std::runtime_error(
        "the grid is too coarse: no grid cell lies entirely inside the domain (/domain) (use more cells)");
  std::vector<long long> unknown_of(splines, -1);
  long long unknowns = 0;
  for (std::size_t s : basis.relevant) {
    if (!inner[s]) continue;
    unknown_of[s] = unknowns++;
    basis.unknown_spline.push_back(static_cast<std::size_t>(basis.relevant_of[s]));
  }
  const std::vector<char> block_ok = full_inner_blocks(grid, inner);
  const int n = grid.degree;
  for (std::size_t s : basis.relevant) {
    const long long row = basis.relevant_of[s];
    if (inner[s]) {
      entries.emplace_back(row, unknown_of[s], 1.0);
      continue;
    }
    const auto j = grid.spline_index(s);
    const std::array<int, D> best = nearest_inner_array<D>(grid, block_ok, j);
    int total = 1;
    for (int a = 0; a < D; ++a) total *= n + 1;
    for (int k = 0; k < total; ++k) {
      std::array<int, D> i{};
      double weight = 1.0;
      int rest = k;
      for (int a = 0; a < D; ++a) {
        const int m = rest % (n + 1);
        rest /= n + 1;
        i[a] = best[a] + m;
        weight *= lagrange_weight(n, m, static_cast<double>(j[a] - best[a]));
      }
      entries.emplace_back(row, unknown_of[grid.spline_linear(i)], weight);
    }
  }
  basis.extension.resize(rows, static_cast<Eigen::Index>(unknowns));
  basis.extension.setFromTriplets(entries.begin(), entries.end());
  return basis;
}

template SplineBasis<2> build_basis<2>(const BackgroundGrid<2>&, const std::vector<char>&, const std::vector<char>&,
                                       BasisKind);
template SplineBasis<3> build_basis<3>(const BackgroundGrid<3>&, const std::vector<char>&, const std::vector<char>&,
                                       BasisKind);

}  // namespace sage::solver
