#pragma once

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace surgical_sim::core {

/// Symmetric positive-definite block-tridiagonal system with 6x6 blocks, solved by block LDL^T
/// (block Thomas): D_0 = A_00, L_i = A_{i,i-1} D_{i-1}^-1, D_i = A_ii - L_i A_{i,i-1}^T.
/// O(n) factorization and solve; storage sized once in the constructor, factorize() and solve()
/// allocate nothing.
class BlockTridiagonalSolver {
 public:
  using Block = Eigen::Matrix<double, 6, 6>;

  /// @param num_blocks number of 6x6 diagonal blocks n, >= 1.
  /// @throws std::invalid_argument "block_tridiagonal.num_blocks" if n < 1.
  explicit BlockTridiagonalSolver(int num_blocks);

  int numBlocks() const { return static_cast<int>(diagonal_.size()); }
  /// Zeroes every block of A.
  void setZero();
  /// Diagonal block A_ii, i in [0, n).
  Block& diagonal(int i) { return diagonal_[i]; }
  /// Sub-diagonal block A_{i+1,i}, i in [0, n-1); the super-diagonal is its transpose.
  Block& lower(int i) { return lower_[i]; }
  const Block& diagonal(int i) const { return diagonal_[i]; }
  const Block& lower(int i) const { return lower_[i]; }

  /// Block LDL^T of A. Returns false if a pivot block is not positive definite.
  bool factorize();
  /// Solves A x = b in place (x on entry holds b), size 6n.
  void solve(Eigen::Ref<Eigen::VectorXd> x) const;
  /// y = A v, sizes 6n.
  void multiply(const Eigen::VectorXd& v, Eigen::VectorXd& y) const;
  /// Assembled A as a full symmetric sparse matrix (tests, diagnostics).
  Eigen::SparseMatrix<double> toSparse() const;

 private:
  std::vector<Block> diagonal_;
  std::vector<Block> lower_;
  std::vector<Block> factor_lower_;        ///< L_i (index i-1 for block row i)
  std::vector<Eigen::LLT<Block>> pivots_;  ///< LL^T of D_i
};

}  // namespace surgical_sim::core
