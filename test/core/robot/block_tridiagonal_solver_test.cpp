#include <gtest/gtest.h>

#include <random>

#include "surgical_sim/core/robot/block_tridiagonal_solver.h"
#include "surgical_sim/core/solve/cholmod_solver.h"

namespace surgical_sim::core {
namespace {

TEST(BlockTridiagonalSolver, MatchesCholmodOnTheAssembledMatrix) {
  const int n = 17;
  BlockTridiagonalSolver btd(n);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  using Block = BlockTridiagonalSolver::Block;
  for (int i = 0; i < n; ++i) {
    Block A;
    for (int k = 0; k < 36; ++k) A.data()[k] = u(rng);
    btd.diagonal(i) = A * A.transpose() + 20.0 * Block::Identity();
    if (i + 1 < n)
      for (int k = 0; k < 36; ++k) btd.lower(i).data()[k] = 2.0 * u(rng);
  }
  ASSERT_TRUE(btd.factorize());
  Eigen::VectorXd b(6 * n);
  for (int k = 0; k < b.size(); ++k) b[k] = u(rng);
  Eigen::VectorXd x = b;
  btd.solve(x);

  const Eigen::SparseMatrix<double> A = btd.toSparse();
  CholmodSolver chol;
  chol.analyzePattern(A);
  ASSERT_TRUE(chol.factorize(A));
  Eigen::VectorXd y(6 * n);
  chol.solve(b, y);
  EXPECT_LT((x - y).norm(), 1e-10 * y.norm());
  Eigen::VectorXd Ax(6 * n);
  btd.multiply(x, Ax);
  EXPECT_LT((Ax - b).norm(), 1e-10 * b.norm());
  EXPECT_LT((A * x - b).norm(), 1e-10 * b.norm());
}

TEST(BlockTridiagonalSolver, ReportsIndefiniteMatrixAndRejectsBadSize) {
  BlockTridiagonalSolver btd(2);
  btd.diagonal(0) = BlockTridiagonalSolver::Block::Identity();
  btd.diagonal(1) = -BlockTridiagonalSolver::Block::Identity();
  EXPECT_FALSE(btd.factorize());
  EXPECT_THROW(BlockTridiagonalSolver(0), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
