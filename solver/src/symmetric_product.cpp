#include "symmetric_product.hpp"

#include "threads.hpp"

namespace sage::solver {

SymmetricProduct::SymmetricProduct(const Eigen::SparseMatrix<double>& lower) : lower_(lower) {
  const int threads = thread_count();
  // Slices of about equal entries: column c starts at outer[c].
  const Eigen::Index columns = lower.cols();
  const double entries = static_cast<double>(lower.nonZeros());
  first_column_.push_back(0);
  Eigen::Index c = 0;
  for (int t = 1; t < threads; ++t) {
    const double target = entries * t / threads;
    while (c < columns && static_cast<double>(lower.outerIndexPtr()[c]) < target) ++c;
    first_column_.push_back(c);
  }
  first_column_.push_back(columns);
  scatter_.resize(static_cast<std::size_t>(threads));
  for (int t = 0; t < threads; ++t) scatter_[static_cast<std::size_t>(t)].resize(columns - first_column_[t]);
}

void SymmetricProduct::apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const Eigen::Index columns = lower_.cols();
  const int slices = static_cast<int>(scatter_.size());
  y.resize(columns);
  const int* outer = lower_.outerIndexPtr();
  const int* inner = lower_.innerIndexPtr();
  const double* values = lower_.valuePtr();
  const bool compressed = lower_.isCompressed();
  const int* nonzeros = lower_.innerNonZeroPtr();
  // One slice per thread (a loop, so that a smaller team, as inside
  // another parallel region, still does them all).
#pragma omp parallel num_threads(slices)
  {
#pragma omp for schedule(static, 1)
    for (int t = 0; t < slices; ++t) {
      const Eigen::Index first = first_column_[static_cast<std::size_t>(t)];
      const Eigen::Index last = first_column_[static_cast<std::size_t>(t) + 1];
      Eigen::VectorXd& scatter = scatter_[static_cast<std::size_t>(t)];
      scatter.setZero();
      double* spread = scatter.data();  // spread[i - first] for rows i >= first
      for (Eigen::Index c = first; c < last; ++c) {
        int k = outer[c];
        const int end = compressed ? outer[c + 1] : outer[c] + nonzeros[c];
        const double xc = x[c];
        double gathered = 0.0;
        if (k < end && inner[k] == c) gathered += values[k++] * xc;  // the diagonal comes first (rows sorted)
        for (; k < end; ++k) {
          const int i = inner[k];
          const double v = values[k];
          gathered += v * x[i];
          spread[i - first] += v * xc;
        }
        spread[c - first] += gathered;
      }
    }
    // y[i] = the slices' sums, each thread over its own rows.
#pragma omp for schedule(static)
    for (Eigen::Index i = 0; i < columns; ++i) {
      double sum = 0.0;
      for (int s = 0; s < slices && first_column_[static_cast<std::size_t>(s)] <= i; ++s)
        sum += scatter_[static_cast<std::size_t>(s)][i - first_column_[static_cast<std::size_t>(s)]];
      y[i] = sum;
    }
  }
}

}  // namespace sage::solver
