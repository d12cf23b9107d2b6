#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

namespace surgical_sim::core {

/// 3x3 block-Jacobi preconditioner of the trailing unknowns [first, n) of a symmetric matrix:
/// the inverses of its diagonal 3x3 blocks, the blocks starting at first (a trailing partial block
/// gets identity in its unused slots). first = 0 covers the whole matrix (node blocks when the
/// unknowns are node coordinates). build() and apply() allocate nothing.
class BlockJacobi {
 public:
  /// Sizes the blocks for the unknowns [first, n), 0 <= first <= n.
  void resize(Eigen::Index first, Eigen::Index n);
  /// Inverts the diagonal blocks of A (n x n, compressed). Returns false if a block is not
  /// positive definite or its inverse is not finite.
  bool build(const Eigen::SparseMatrix<double>& A);
  /// z[first, n) = (block diagonal)^-1 r[first, n); z's other entries are left unchanged.
  /// r and z of size n.
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const;

 private:
  Eigen::Index first_ = 0;
  Eigen::Index size_ = 0;
  std::vector<Eigen::Matrix3d> inverse_blocks_;
};

}  // namespace surgical_sim::core
