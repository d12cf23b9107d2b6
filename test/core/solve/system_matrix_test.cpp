#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "solve_test_util.h"
#include "surgical_sim/core/solve/system_matrix.h"

namespace surgical_sim::core::test {
namespace {

/// A = mass_coefficient diag(mass) + stiffness_coefficient K, densely.
Eigen::MatrixXd expectedSystem(const Eigen::VectorXd& mass, const Eigen::SparseMatrix<double>& K) {
  Eigen::MatrixXd A = 0.5 * Eigen::MatrixXd(K);
  A.diagonal() += 2.0 * mass;
  return A;
}

void expectAssembles(const Eigen::SparseMatrix<double>& K, const char* context) {
  const Eigen::VectorXd mass = Eigen::VectorXd::LinSpaced(K.rows(), 1.0, 2.0);
  SystemMatrix system;
  system.setPattern(K);
  EXPECT_TRUE(system.matchesPattern(K)) << context;
  system.assemble(mass, 2.0, K, 0.5);
  EXPECT_LT((Eigen::MatrixXd(system.matrix()) - expectedSystem(mass, K)).norm(), 1e-12 * K.norm())
      << context;
}

TEST(SystemMatrix, AssemblesMassAndStiffnessWithAndWithoutStoredDiagonal) {
  expectAssembles(spdTestMatrix(3), "node-block pattern (diagonal stored)");
  // Off-diagonal couplings only: the diagonal entries are added to the pattern.
  std::vector<Eigen::Triplet<double>> entries = {
      {0, 2, 1.5}, {2, 0, 1.5}, {1, 3, -0.5}, {3, 1, -0.5}, {1, 1, 4.0}};
  Eigen::SparseMatrix<double> K(4, 4);
  K.setFromTriplets(entries.begin(), entries.end());
  K.makeCompressed();
  expectAssembles(K, "pattern without some diagonal entries");
}

}  // namespace
}  // namespace surgical_sim::core::test
