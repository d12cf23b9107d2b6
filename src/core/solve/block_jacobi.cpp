#include "surgical_sim/core/solve/block_jacobi.h"

#include <Eigen/Cholesky>
#include <algorithm>

namespace surgical_sim::core {

void BlockJacobi::resize(Eigen::Index first, Eigen::Index n) {
  first_ = first;
  size_ = n;
  inverse_blocks_.assign(static_cast<size_t>((n - first + 2) / 3), Eigen::Matrix3d::Zero());
}

bool BlockJacobi::build(const Eigen::SparseMatrix<double>& A) {
  for (Eigen::Matrix3d& block : inverse_blocks_) block.setZero();
  for (Eigen::Index j = first_; j < size_; ++j) {
    const Eigen::Index block = (j - first_) / 3;
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      if (it.row() >= first_ && (it.row() - first_) / 3 == block) {
        inverse_blocks_[static_cast<size_t>(block)]((it.row() - first_) % 3, (j - first_) % 3) =
            it.value();
      }
    }
  }
  for (Eigen::Index k = size_ - first_; k % 3 != 0; ++k) {
    inverse_blocks_.back()(k % 3, k % 3) = 1.0;
  }
  for (Eigen::Matrix3d& block : inverse_blocks_) {
    Eigen::LLT<Eigen::Matrix3d> llt(block);
    if (llt.info() != Eigen::Success) return false;
    block = llt.solve(Eigen::Matrix3d::Identity());
    if (!block.allFinite()) return false;
  }
  return true;
}

void BlockJacobi::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  for (Eigen::Index start = first_, b = 0; start < size_; start += 3, ++b) {
    const Eigen::Index m = std::min<Eigen::Index>(3, size_ - start);
    z.segment(start, m).noalias() =
        inverse_blocks_[static_cast<size_t>(b)].topLeftCorner(m, m) * r.segment(start, m);
  }
}

}  // namespace surgical_sim::core
