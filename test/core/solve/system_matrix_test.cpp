#include "surgical_sim/core/solve/system_matrix.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <vector>

namespace surgical_sim::core {
namespace {

/// Symmetric 6 x 6 stiffness pattern with structural zeros, without the diagonal entries of
/// rows 0, 3 and 5 (first, middle and last place of their columns), values k_ij = i + 10 j.
Eigen::SparseMatrix<double> stiffnessWithoutSomeDiagonals(bool compressed) {
  const std::vector<std::pair<int, int>> entries = {{1, 1}, {2, 2}, {4, 4}, {0, 1}, {0, 2},
                                                    {1, 3}, {2, 3}, {3, 4}, {4, 5}, {2, 5}};
  Eigen::SparseMatrix<double> K(6, 6);
  for (const auto& [i, j] : entries) {
    K.insert(i, j) = i + 10.0 * j;
    if (i != j) K.insert(j, i) = j + 10.0 * i;
  }
  if (compressed) K.makeCompressed();
  return K;
}

TEST(SystemMatrix, PatternIsStiffnessPlusDiagonalAndAssemblyScalesBoth) {
  for (bool compressed : {true, false}) {
    const Eigen::SparseMatrix<double> K = stiffnessWithoutSomeDiagonals(compressed);
    SystemMatrix system;
    system.setPattern(K);
    EXPECT_TRUE(system.matchesPattern(K));
    const Eigen::SparseMatrix<double>& A = system.matrix();
    ASSERT_TRUE(A.isCompressed());
    // The pattern set up is K + I, with the values of K + I.
    Eigen::SparseMatrix<double> identity(6, 6);
    identity.setIdentity();
    Eigen::SparseMatrix<double> expected = K + identity;
    expected.makeCompressed();
    ASSERT_EQ(A.nonZeros(), expected.nonZeros());
    for (Eigen::Index j = 0; j <= 6; ++j)
      EXPECT_EQ(A.outerIndexPtr()[j], expected.outerIndexPtr()[j]);
    for (Eigen::Index p = 0; p < A.nonZeros(); ++p) {
      EXPECT_EQ(A.innerIndexPtr()[p], expected.innerIndexPtr()[p]) << p;
      EXPECT_EQ(A.valuePtr()[p], expected.valuePtr()[p]) << p;
    }
    // A = 2 diag(m) + 0.5 K through the index maps.
    const Eigen::VectorXd mass = Eigen::VectorXd::LinSpaced(6, 1.0, 6.0);
    Eigen::SparseMatrix<double> K_values = K;
    K_values.makeCompressed();
    system.assemble(mass, 2.0, K_values, 0.5);
    const Eigen::MatrixXd reference =
        Eigen::MatrixXd(2.0 * mass.asDiagonal()) + 0.5 * Eigen::MatrixXd(K);
    EXPECT_EQ(Eigen::MatrixXd(system.matrix()), reference);
  }
}

}  // namespace
}  // namespace surgical_sim::core
