#include "surgical_sim/core/contact/projected_gauss_seidel.h"

#include <gtest/gtest.h>

#include <random>

namespace surgical_sim::core {
namespace {

TEST(ProjectedGaussSeidel, SatisfiesComplementarityOnRandomSpdProblems) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const int m = 3 + trial;
    Eigen::MatrixXd B(m, m);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) B(i, j) = u(rng);
    const Eigen::MatrixXd W = 1e-4 * (B * B.transpose() + 0.5 * Eigen::MatrixXd::Identity(m, m));
    Eigen::VectorXd q(m);
    for (int i = 0; i < m; ++i) q[i] = 1e-3 * u(rng);  // some penetrating, some separated [m]
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(m);
    const double tol = 1e-12;
    const PgsReport report = solveLcpProjectedGaussSeidel(W, q, 100000, tol, lambda);
    ASSERT_TRUE(report.converged) << report.residual;
    const Eigen::VectorXd gap = q + W * lambda;
    EXPECT_GE(lambda.minCoeff(), 0.0);
    EXPECT_GE(gap.minCoeff(), -1e-10);
    for (int i = 0; i < m; ++i) EXPECT_LE(std::abs(lambda[i] * gap[i]), 1e-9 * lambda.norm());
  }
}

TEST(ProjectedGaussSeidel, SingleContactIsPenetrationOverCompliance) {
  Eigen::MatrixXd W(1, 1);
  W(0, 0) = 2e-3;  // m/N
  Eigen::VectorXd q(1), lambda = Eigen::VectorXd::Zero(1);
  q[0] = -1e-3;
  solveLcpProjectedGaussSeidel(W, q, 10, 1e-15, lambda);
  EXPECT_NEAR(lambda[0], 0.5, 1e-12);
  q[0] = 1e-3;  // separated: no force
  solveLcpProjectedGaussSeidel(W, q, 10, 1e-15, lambda);
  EXPECT_EQ(lambda[0], 0.0);
}

}  // namespace
}  // namespace surgical_sim::core
