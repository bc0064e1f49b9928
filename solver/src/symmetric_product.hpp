#pragma once
// y = A x for a symmetric A given by its lower triangle, on all cores.
// Eigen's selfadjointView product runs on one core; here each thread
// takes a slice of the columns (balanced by their entries), gathers its
// own columns' rows into y and scatters the transposed entries into a
// buffer of its own, and the buffers are summed at the end.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace sage::solver {

class SymmetricProduct {
 public:
  explicit SymmetricProduct(const Eigen::SparseMatrix<double>& lower);

  /// y = A x (y resized). Not reentrant: the buffers are the object's.
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;

 private:
  const Eigen::SparseMatrix<double>& lower_;
  std::vector<Eigen::Index> first_column_;        // per thread's slice, and the end
  mutable std::vector<Eigen::VectorXd> scatter_;  // per thread: rows from its slice's first column on
};

}  // namespace sage::solver
