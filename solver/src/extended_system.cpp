#include <sage/solver/extended_system.hpp>

#include <algorithm>
#include <stdexcept>

namespace sage::solver {

namespace {

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

/// A's rows without the empty slots: row r's (relevant column, value)
/// pairs are entries[start[r] .. start[r + 1]).
struct BandRows {
  std::vector<std::size_t> start;
  std::vector<Entry> entries;
};

template <int D>
BandRows band_rows(const SplineBasis<D>& basis, const std::vector<double>& band) {
  const BackgroundGrid<D>& grid = basis.grid;
  const int n = grid.degree, width = 2 * n + 1;
  int stencil = 1;
  for (int a = 0; a < D; ++a) stencil *= width;
  const std::size_t relevant = basis.relevant.size();
  if (band.size() != relevant * static_cast<std::size_t>(stencil) ||
      static_cast<std::size_t>(basis.extension.rows()) != relevant)
    throw std::invalid_argument("the band does not match the basis");
  std::vector<long long> shift(static_cast<std::size_t>(stencil));  // slot -> global spline offset
  for (int o = 0; o < stencil; ++o) {
    long long s = 0, stride = 1;
    int rest = o;
    for (int a = 0; a < D; ++a) {
      s += (rest % width - n) * stride;
      rest /= width;
      stride *= grid.splines_along(a);
    }
    shift[static_cast<std::size_t>(o)] = s;
  }
  BandRows rows;
  rows.start.assign(relevant + 1, 0);
  for (std::size_t r = 0; r < relevant; ++r) {
    const double* row = band.data() + r * static_cast<std::size_t>(stencil);
    const auto spline = static_cast<long long>(basis.relevant[r]);
    for (int o = 0; o < stencil; ++o) {
      if (row[o] == 0.0) continue;
      const long long j = basis.relevant_of[static_cast<std::size_t>(spline + shift[static_cast<std::size_t>(o)])];
      rows.entries.push_back({static_cast<int>(j), row[o]});
    }
    rows.start[r + 1] = rows.entries.size();
  }
  return rows;
}

}  // namespace

template <int D>
Eigen::SparseMatrix<double> band_matrix(const SplineBasis<D>& basis, const std::vector<double>& band) {
  const BandRows rows = band_rows(basis, band);
  const auto relevant = static_cast<Eigen::Index>(basis.relevant.size());
  Eigen::SparseMatrix<double, Eigen::RowMajor> a(relevant, relevant);
  a.reserve(static_cast<Eigen::Index>(rows.entries.size()));
  for (Eigen::Index r = 0; r < relevant; ++r)
    for (std::size_t k = rows.start[static_cast<std::size_t>(r)]; k < rows.start[static_cast<std::size_t>(r) + 1]; ++k)
      a.insert(r, rows.entries[k].row) = rows.entries[k].value;
  return a;
}

template <int D>
Eigen::SparseMatrix<double> extended_system(const SplineBasis<D>& basis, const std::vector<double>& band) {
  const BandRows rows = band_rows(basis, band);
  const std::vector<std::size_t>& a_start = rows.start;
  const std::vector<Entry>& a_entries = rows.entries;
  const std::size_t relevant = basis.relevant.size();
  const Eigen::SparseMatrix<double>& E = basis.extension;
  const Eigen::Index unknowns = E.cols();
  const Eigen::SparseMatrix<double, Eigen::RowMajor> rows_of_e = E;

  // Column p of E^T A E is E^T (A e) with e = E(:, p): A e from the rows
  // of A at e's splines (A is symmetric), then E^T of that; only rows
  // i >= p (the lower triangle).
  std::vector<std::vector<Entry>> lower(static_cast<std::size_t>(unknowns));
#pragma omp parallel
  {
    Accumulator splines(relevant), result(static_cast<std::size_t>(unknowns));
#pragma omp for schedule(dynamic, 32)
    for (Eigen::Index p = 0; p < unknowns; ++p) {
      for (Eigen::SparseMatrix<double>::InnerIterator e(E, p); e; ++e) {
        const auto r = static_cast<std::size_t>(e.row());
        for (std::size_t k = a_start[r]; k < a_start[r + 1]; ++k)
          splines.add(static_cast<std::size_t>(a_entries[k].row), e.value() * a_entries[k].value);
      }
      for (const int j : splines.list()) {
        const double y = splines.take(j);
        // Row j of E, columns increasing: walk back from the last while >= p.
        const auto begin = rows_of_e.outerIndexPtr()[j], end = rows_of_e.outerIndexPtr()[j + 1];
        for (auto t = end - 1; t >= begin && rows_of_e.innerIndexPtr()[t] >= p; --t)
          result.add(static_cast<std::size_t>(rows_of_e.innerIndexPtr()[t]), rows_of_e.valuePtr()[t] * y);
      }
      splines.list().clear();
      std::vector<int>& list = result.list();
      std::sort(list.begin(), list.end());
      std::vector<Entry>& column = lower[static_cast<std::size_t>(p)];
      column.reserve(list.size());
      for (const int i : list) column.push_back({i, result.take(i)});
      list.clear();
    }
  }

  Eigen::SparseMatrix<double> system(unknowns, unknowns);
  std::size_t total = 0;
  for (const auto& column : lower) total += column.size();
  system.resizeNonZeros(static_cast<Eigen::Index>(total));
  int* outer = system.outerIndexPtr();
  int* inner = system.innerIndexPtr();
  double* values = system.valuePtr();
  std::size_t k = 0;
  for (Eigen::Index p = 0; p < unknowns; ++p) {
    outer[p] = static_cast<int>(k);
    for (const Entry& entry : lower[static_cast<std::size_t>(p)]) {
      inner[k] = entry.row;
      values[k] = entry.value;
      ++k;
    }
    std::vector<Entry>().swap(lower[static_cast<std::size_t>(p)]);
  }
  outer[unknowns] = static_cast<int>(k);
  return system;
}

template Eigen::SparseMatrix<double> extended_system<2>(const SplineBasis<2>&, const std::vector<double>&);
template Eigen::SparseMatrix<double> extended_system<3>(const SplineBasis<3>&, const std::vector<double>&);
template Eigen::SparseMatrix<double> band_matrix<2>(const SplineBasis<2>&, const std::vector<double>&);
template Eigen::SparseMatrix<double> band_matrix<3>(const SplineBasis<3>&, const std::vector<double>&);

}  // namespace sage::solver
