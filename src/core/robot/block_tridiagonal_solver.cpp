#include "surgical_sim/core/robot/block_tridiagonal_solver.h"

#include <stdexcept>

namespace surgical_sim::core {

BlockTridiagonalSolver::BlockTridiagonalSolver(int num_blocks) {
  if (num_blocks < 1)
    throw std::invalid_argument("block_tridiagonal.num_blocks = " + std::to_string(num_blocks) +
                                " is out of range: must be >= 1");
  diagonal_.assign(num_blocks, Block::Zero());
  lower_.assign(num_blocks - 1, Block::Zero());
  factor_lower_.assign(num_blocks - 1, Block::Zero());
  pivots_.resize(num_blocks);
}

void BlockTridiagonalSolver::setZero() {
  for (Block& b : diagonal_) b.setZero();
  for (Block& b : lower_) b.setZero();
}

bool BlockTridiagonalSolver::factorize() {
  const int n = numBlocks();
  Block D = diagonal_[0];
  for (int i = 0;; ++i) {
    pivots_[i].compute(D);
    if (pivots_[i].info() != Eigen::Success || !D.allFinite()) return false;
    if (i + 1 == n) return true;
    // L_{i+1} = B D^-1 with B = A_{i+1,i}: L^T = D^-1 B^T.
    factor_lower_[i] = pivots_[i].solve(lower_[i].transpose()).transpose();
    D = diagonal_[i + 1] - factor_lower_[i] * lower_[i].transpose();
  }
}

void BlockTridiagonalSolver::solve(Eigen::Ref<Eigen::VectorXd> x) const {
  const int n = numBlocks();
  for (int i = 1; i < n; ++i)
    x.segment<6>(6 * i) -= factor_lower_[i - 1] * x.segment<6>(6 * (i - 1));
  for (int i = 0; i < n; ++i) x.segment<6>(6 * i) = pivots_[i].solve(x.segment<6>(6 * i));
  for (int i = n - 2; i >= 0; --i)
    x.segment<6>(6 * i) -= factor_lower_[i].transpose() * x.segment<6>(6 * (i + 1));
}

void BlockTridiagonalSolver::multiply(const Eigen::VectorXd& v, Eigen::VectorXd& y) const {
  const int n = numBlocks();
  for (int i = 0; i < n; ++i) {
    y.segment<6>(6 * i) = diagonal_[i] * v.segment<6>(6 * i);
    if (i > 0) y.segment<6>(6 * i) += lower_[i - 1] * v.segment<6>(6 * (i - 1));
    if (i + 1 < n) y.segment<6>(6 * i) += lower_[i].transpose() * v.segment<6>(6 * (i + 1));
  }
}

Eigen::SparseMatrix<double> BlockTridiagonalSolver::toSparse() const {
  const int n = numBlocks();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(36 * (3 * n));
  for (int i = 0; i < n; ++i)
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) {
        t.emplace_back(6 * i + r, 6 * i + c, diagonal_[i](r, c));
        if (i + 1 < n) {
          t.emplace_back(6 * (i + 1) + r, 6 * i + c, lower_[i](r, c));
          t.emplace_back(6 * i + c, 6 * (i + 1) + r, lower_[i](r, c));
        }
      }
  Eigen::SparseMatrix<double> A(6 * n, 6 * n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

}  // namespace surgical_sim::core
