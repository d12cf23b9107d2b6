#include "surgical_sim/core/solve/dirichlet_projection.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "solve_test_util.h"
#include "surgical_sim/core/solve/cholmod_solver.h"

namespace surgical_sim::core::test {
namespace {

TEST(DirichletProjection, ConstrainedDofsTakePrescribedValuesOthersSolveReducedSystem) {
  Eigen::SparseMatrix<double> A = spdTestMatrix(11);
  const Eigen::Index n = A.rows();
  const Eigen::MatrixXd dense = Eigen::MatrixXd(A);
  const std::vector<int> dofs = {0, 4, 7, 20, static_cast<int>(n) - 1};
  Eigen::VectorXd prescribed = Eigen::VectorXd::Zero(n);
  for (size_t k = 0; k < dofs.size(); ++k) prescribed[dofs[k]] = 0.1 * (k + 1.0) - 0.25;
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, 1.0, -3.0);
  const Eigen::VectorXd b_original = b;

  std::vector<std::uint8_t> mask(static_cast<size_t>(n), 0);
  ASSERT_TRUE(markDirichletDofs(dofs, mask));
  const Eigen::Index nonzeros = A.nonZeros();
  applyDirichletRhs(A, mask, prescribed, b);
  projectDirichletMatrix(mask, A);
  EXPECT_EQ(A.nonZeros(), nonzeros);  // pattern kept
  const Eigen::MatrixXd projected = Eigen::MatrixXd(A);
  for (const int d : dofs) {
    EXPECT_EQ(projected(d, d), 1.0);
    EXPECT_EQ(projected.row(d).cwiseAbs().sum(), 1.0);
    EXPECT_EQ(projected.col(d).cwiseAbs().sum(), 1.0);
  }

  CholmodSolver solver;
  solver.analyzePattern(A);
  ASSERT_TRUE(solver.factorize(A));
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  ASSERT_TRUE(solver.solve(b, u).ok);
  for (const int d : dofs) EXPECT_EQ(u[d], prescribed[d]);

  // Dense reduced solve: A_ff u_f = b_f - A_fc g_c.
  std::vector<int> free;
  for (int i = 0; i < n; ++i)
    if (mask[static_cast<size_t>(i)] == 0) free.push_back(i);
  const Eigen::Index nf = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd a_ff(nf, nf);
  Eigen::VectorXd rhs(nf);
  for (Eigen::Index r = 0; r < nf; ++r) {
    rhs[r] = b_original[free[r]];
    for (const int d : dofs) rhs[r] -= dense(free[r], d) * prescribed[d];
    for (Eigen::Index c = 0; c < nf; ++c) a_ff(r, c) = dense(free[r], free[c]);
  }
  const Eigen::VectorXd u_f = a_ff.llt().solve(rhs);
  for (Eigen::Index r = 0; r < nf; ++r) EXPECT_NEAR(u[free[r]], u_f[r], 1e-10 * u_f.norm());
}

TEST(DirichletProjection, OutOfRangeDofIsReported) {
  std::vector<std::uint8_t> mask(6, 0);
  EXPECT_FALSE(markDirichletDofs({1, 6}, mask));
  EXPECT_EQ(mask[1], 1);
  EXPECT_TRUE(markDirichletDofs({2}, mask));
  EXPECT_EQ(mask[1], 0);
}

TEST(DirichletProjection, ZeroEntries) {
  Eigen::VectorXd v = Eigen::VectorXd::Ones(5);
  zeroDirichletEntries({0, 3}, v);
  EXPECT_EQ(v, (Eigen::VectorXd(5) << 0, 1, 1, 0, 1).finished());
}

}  // namespace
}  // namespace surgical_sim::core::test
