#include "surgical_sim/core/contact/lcp_active_set.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

namespace surgical_sim::core {
namespace {

/// Brute force: the LCP with W positive definite has one solution; find the support whose
/// linear solve is feasible and complementary.
Eigen::VectorXd bruteForceLcp(const Eigen::MatrixXd& W, const Eigen::VectorXd& q) {
  const int m = static_cast<int>(q.size());
  for (int mask = 0; mask < (1 << m); ++mask) {
    std::vector<int> support;
    for (int i = 0; i < m; ++i) {
      if (mask & (1 << i)) support.push_back(i);
    }
    const int a = static_cast<int>(support.size());
    Eigen::MatrixXd Waa(a, a);
    Eigen::VectorXd rhs(a);
    for (int r = 0; r < a; ++r) {
      rhs[r] = -q[support[r]];
      for (int c = 0; c < a; ++c) Waa(r, c) = W(support[r], support[c]);
    }
    const Eigen::VectorXd la = Waa.ldlt().solve(rhs);
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(m);
    for (int r = 0; r < a; ++r) lambda[support[r]] = la[r];
    if (lambda.minCoeff() < -1e-12) continue;
    if ((q + W * lambda).minCoeff() < -1e-12) continue;
    return lambda;
  }
  return Eigen::VectorXd::Constant(m, -1.0);
}

TEST(LcpActiveSet, MatchesBruteForceFromAnyStart) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  LcpActiveSetWorkspace workspace(8);
  for (int trial = 0; trial < 60; ++trial) {
    const int m = 1 + trial % 8;
    Eigen::MatrixXd B(m, m);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) B(i, j) = u(rng);
    const Eigen::MatrixXd W = 1e-4 * (B * B.transpose() + 0.2 * Eigen::MatrixXd::Identity(m, m));
    Eigen::VectorXd q(m);
    for (int i = 0; i < m; ++i) q[i] = 1e-3 * u(rng);
    const Eigen::VectorXd reference = bruteForceLcp(W, q);
    ASSERT_GE(reference.minCoeff(), 0.0);
    // Start from nothing, from everything active, and from a random support.
    for (int start = 0; start < 3; ++start) {
      Eigen::VectorXd lambda(m);
      for (int i = 0; i < m; ++i) lambda[i] = start == 0 ? 0.0 : start == 1 ? 1.0 : u(rng);
      const PgsReport report = refineLcpActiveSet(W, q, 1e-15, 8 * m, lambda, workspace);
      ASSERT_TRUE(report.converged) << "trial " << trial << " start " << start;
      EXPECT_LE((lambda - reference).norm(), 1e-8 * (1.0 + reference.norm()));
      EXPECT_LE(report.residual, 1e-9 * q.cwiseAbs().maxCoeff());  // regularization only
    }
  }
}

TEST(LcpActiveSet, SingleContactIsPenetrationOverCompliance) {
  LcpActiveSetWorkspace workspace(1);
  Eigen::MatrixXd W(1, 1);
  W(0, 0) = 2e-3;  // m/N
  Eigen::VectorXd q(1), lambda = Eigen::VectorXd::Zero(1);
  q[0] = -1e-3;
  ASSERT_TRUE(refineLcpActiveSet(W, q, 0.0, 4, lambda, workspace).converged);
  EXPECT_NEAR(lambda[0], 0.5, 1e-9);  // 1e-3 m / 2e-3 m/N, up to the 1e-10 regularization
  q[0] = 1e-3;                        // separated: no force
  ASSERT_TRUE(refineLcpActiveSet(W, q, 0.0, 4, lambda, workspace).converged);
  EXPECT_EQ(lambda[0], 0.0);
}

TEST(LcpActiveSet, RedundantContactsGiveTheUniqueTotalForce) {
  // Two identical rows (one tip touching two triangles at a shared vertex): W is singular, the
  // split is not unique but the total force is q / w.
  LcpActiveSetWorkspace workspace(2);
  Eigen::MatrixXd W = Eigen::MatrixXd::Constant(2, 2, 1e-3);
  Eigen::VectorXd q = Eigen::VectorXd::Constant(2, -2e-3), lambda = Eigen::VectorXd::Zero(2);
  ASSERT_TRUE(refineLcpActiveSet(W, q, 1e-12, 8, lambda, workspace).converged);
  EXPECT_NEAR(lambda.sum(), 2.0, 1e-6);
  EXPECT_GE(lambda.minCoeff(), 0.0);
}

TEST(LcpActiveSet, RefusesProblemsLargerThanTheWorkspace) {
  LcpActiveSetWorkspace workspace(1);
  const Eigen::MatrixXd W = Eigen::MatrixXd::Identity(2, 2);
  const Eigen::VectorXd q = -Eigen::VectorXd::Ones(2);
  Eigen::VectorXd lambda = Eigen::VectorXd::Constant(2, 7.0);
  EXPECT_FALSE(refineLcpActiveSet(W, q, 1e-12, 8, lambda, workspace).converged);
  EXPECT_EQ(lambda, Eigen::VectorXd::Constant(2, 7.0));
}

}  // namespace
}  // namespace surgical_sim::core
