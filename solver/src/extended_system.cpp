#include <sage/solver/extended_system.hpp>

#include "threads.hpp"

#include <algorithm>
#include <stdexcept>

namespace sage::solver {

namespace {

/// Columns of the product computed between two appends to the result.
constexpr Eigen::Index kColumnsAtOnce = 4096;

struct Entry {
  int row;
  double value;
};

/// A dense vector that remembers which entries were touched, so that
/// clearing and listing them costs only their number.
class Accumulator {
 public:
  explicit Accumulator(std::size_t size) : value_(size, 0.0), touched_(size, 0) {}
  void add(std::size_t i, double v) {
    if (!touched_[i]) {
      touched_[i] = 1;
      list_.push_back(static_cast<int>(i));
    }
    value_[i] += v;
  }
  std::vector<int>& list() { return list_; }
  double take(int i) {
    const double v = value_[static_cast<std::size_t>(i)];
    value_[static_cast<std::size_t>(i)] = 0.0;
    touched_[static_cast<std::size_t>(i)] = 0;
    return v;
  }

 private:
  std::vector<double> value_;
  std::vector<char> touched_;
  std::vector<int> list_;
};

/// Where the band's slots point: row r's slot o is the relevant spline
/// relevant_of[relevant[r] + shift[o]] (slots of splines that are not
/// relevant hold 0). Read in place: a list of the band's entries would
/// take twice the band's memory.
struct BandLayout {
  int stencil = 1;
  std::vector<long long> shift;
};

template <int D>
BandLayout band_layout(const SplineBasis<D>& basis, const std::vector<double>& band) {
  const BackgroundGrid<D>& grid = basis.grid;
  const int n = grid.degree, width = 2 * n + 1;
  BandLayout layout;
  for (int a = 0; a < D; ++a) layout.stencil *= width;
  const std::size_t relevant = basis.relevant.size();
  if (band.size() != relevant * static_cast<std::size_t>(layout.stencil) ||
      static_cast<std::size_t>(basis.extension.rows()) != relevant)
    throw std::invalid_argument("the band does not match the basis");
  layout.shift.resize(static_cast<std::size_t>(layout.stencil));
  for (int o = 0; o < layout.stencil; ++o) {
    long long s = 0, stride = 1;
    int rest = o;
    for (int a = 0; a < D; ++a) {
      s += (rest % width - n) * stride;
      rest /= width;
      stride *= grid.splines_along(a);
    }
    layout.shift[static_cast<std::size_t>(o)] = s;
  }
  return layout;
}

/// Column p of the result is row p of E^T A E (E^T (row p of A E)^T:
/// rows of A are what the band holds), so the result is (E^T A E)^T, or
/// E^T A E itself when A is symmetric; with `lower_only`, only its rows
/// i >= p. Rows sorted in each column.
template <int D>
Eigen::SparseMatrix<double> extended_rows(const SplineBasis<D>& basis, const std::vector<double>& band,
                                          bool lower_only) {
  const BandLayout layout = band_layout(basis, band);
  const auto stencil = static_cast<std::size_t>(layout.stencil);
  const std::size_t relevant = basis.relevant.size();
  const Eigen::SparseMatrix<double>& E = basis.extension;
  const Eigen::Index unknowns = E.cols();
  const Eigen::SparseMatrix<double, Eigen::RowMajor> rows_of_e = E;

  // Row p of A E from the rows of A at e = E(:, p)'s splines, then E^T of
  // it; kColumnsAtOnce columns at a time on all cores, appended in order.
  Eigen::SparseMatrix<double> product(unknowns, unknowns);
  std::vector<std::vector<Entry>> columns(static_cast<std::size_t>(std::min(kColumnsAtOnce, unknowns)));
  std::vector<Accumulator> spline_sums, unknown_sums;  // one of each per thread, kept from chunk to chunk
  for (Eigen::Index first = 0; first < unknowns; first += kColumnsAtOnce) {
    const Eigen::Index last = std::min(unknowns, first + kColumnsAtOnce);
#pragma omp parallel
    {
#pragma omp single
      while (spline_sums.size() < static_cast<std::size_t>(team_size())) {
        spline_sums.emplace_back(relevant);
        unknown_sums.emplace_back(static_cast<std::size_t>(unknowns));
      }
      Accumulator& splines = spline_sums[static_cast<std::size_t>(thread_number())];
      Accumulator& result = unknown_sums[static_cast<std::size_t>(thread_number())];
#pragma omp for schedule(dynamic, 32)
      for (Eigen::Index p = first; p < last; ++p) {
        for (Eigen::SparseMatrix<double>::InnerIterator e(E, p); e; ++e) {
          const auto r = static_cast<std::size_t>(e.row());
          const double* row = band.data() + r * stencil;
          const auto spline = static_cast<long long>(basis.relevant[r]);
          for (std::size_t o = 0; o < stencil; ++o)
            if (row[o] != 0.0)
              splines.add(
                  static_cast<std::size_t>(basis.relevant_of[static_cast<std::size_t>(spline + layout.shift[o])]),
                  e.value() * row[o]);
        }
        const int least = lower_only ? static_cast<int>(p) : 0;
        for (const int j : splines.list()) {
          const double y = splines.take(j);
          // Row j of E, columns increasing: walk back from the last while >= least.
          const auto begin = rows_of_e.outerIndexPtr()[j], end = rows_of_e.outerIndexPtr()[j + 1];
          for (auto t = end - 1; t >= begin && rows_of_e.innerIndexPtr()[t] >= least; --t)
            result.add(static_cast<std::size_t>(rows_of_e.innerIndexPtr()[t]), rows_of_e.valuePtr()[t] * y);
        }
        splines.list().clear();
        std::vector<int>& list = result.list();
        std::sort(list.begin(), list.end());
        std::vector<Entry>& column = columns[static_cast<std::size_t>(p - first)];
        column.clear();
        for (const int i : list) column.push_back({i, result.take(i)});
        list.clear();
      }
    }
    if (first == 0) {
      // Reserved once from the first chunk's mean, with room to spare:
      // pages never written cost no memory, while growing the arrays
      // would copy them beside the new ones.
      std::size_t chunk = 0;
      for (Eigen::Index p = first; p < last; ++p) chunk += columns[static_cast<std::size_t>(p - first)].size();
      product.reserve(static_cast<Eigen::Index>(2.0 * static_cast<double>(chunk) / static_cast<double>(last - first) *
                                                static_cast<double>(unknowns)) +
                      1024);
    }
    for (Eigen::Index p = first; p < last; ++p) {
      product.startVec(p);
      for (const Entry& entry : columns[static_cast<std::size_t>(p - first)])
        product.insertBack(entry.row, p) = entry.value;
    }
  }
  product.finalize();
  return product;
}

}  // namespace

template <int D>
Eigen::SparseMatrix<double> extended_system(const SplineBasis<D>& basis, const std::vector<double>& band) {
  return extended_rows(basis, band, true);
}

template <int D>
Eigen::SparseMatrix<double> extended_product(const SplineBasis<D>& basis, const std::vector<double>& band) {
  Eigen::SparseMatrix<double> transposed = extended_rows(basis, band, false);
  return transposed.transpose();
}

template Eigen::SparseMatrix<double> extended_system<2>(const SplineBasis<2>&, const std::vector<double>&);
template Eigen::SparseMatrix<double> extended_system<3>(const SplineBasis<3>&, const std::vector<double>&);
template Eigen::SparseMatrix<double> extended_product<2>(const SplineBasis<2>&, const std::vector<double>&);
template Eigen::SparseMatrix<double> extended_product<3>(const SplineBasis<3>&, const std::vector<double>&);

}  // namespace sage::solver
