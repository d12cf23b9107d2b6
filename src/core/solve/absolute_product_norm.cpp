#include "surgical_sim/core/solve/absolute_product_norm.h"

#include <cmath>

namespace surgical_sim::core {

double absoluteProductNorm(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& x,
                           Eigen::VectorXd& work) {
  work.setZero();
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    const double xj = std::abs(x[j]);
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      work[it.row()] += std::abs(it.value()) * xj;
    }
  }
  return work.norm();
}

}  // namespace surgical_sim::core
