#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <limits>
#include <random>

#include "surgical_sim/core/robot/box_qp_solver.h"

namespace surgical_sim::core {
namespace {

double objective(const Eigen::MatrixXd& H, const Eigen::VectorXd& c, const Eigen::VectorXd& x) {
  return 0.5 * x.dot(H * x) + c.dot(x);
}

/// Brute force: every assignment of {free, lower, upper} to the variables; keep the feasible
/// stationary points and return the best objective.
double bruteForce(const Eigen::MatrixXd& H, const Eigen::VectorXd& c, const Eigen::VectorXd& lo,
                  const Eigen::VectorXd& hi) {
  const int n = static_cast<int>(c.size());
  int combos = 1;
  for (int i = 0; i < n; ++i) combos *= 3;
  double best = std::numeric_limits<double>::infinity();
  for (int code = 0; code < combos; ++code) {
    Eigen::VectorXd x(n);
    std::vector<int> free;
    int k = code;
    for (int i = 0; i < n; ++i, k /= 3) {
      if (k % 3 == 0) free.push_back(i);
      x[i] = k % 3 == 1 ? lo[i] : hi[i];
    }
    if (!free.empty()) {
      const int m = static_cast<int>(free.size());
      Eigen::MatrixXd Hf(m, m);
      Eigen::VectorXd r(m);
      for (int a = 0; a < m; ++a) {
        r[a] = -c[free[a]];
        for (int j = 0; j < n; ++j)
          if (std::find(free.begin(), free.end(), j) == free.end()) r[a] -= H(free[a], j) * x[j];
        for (int b = 0; b < m; ++b) Hf(a, b) = H(free[a], free[b]);
      }
      const Eigen::VectorXd xf = Hf.ldlt().solve(r);
      for (int a = 0; a < m; ++a) x[free[a]] = xf[a];
    }
    bool feasible = true;
    for (int i = 0; i < n; ++i) feasible &= x[i] >= lo[i] - 1e-12 && x[i] <= hi[i] + 1e-12;
    if (feasible) best = std::min(best, objective(H, c, x));
  }
  return best;
}

TEST(BoxQpSolver, SatisfiesKktAndMatchesBruteForceOnRandomCases) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + trial % 6;
    Eigen::MatrixXd A(n, n);
    for (int k = 0; k < n * n; ++k) A.data()[k] = u(rng);
    const Eigen::MatrixXd H = A * A.transpose() + 0.05 * Eigen::MatrixXd::Identity(n, n);
    Eigen::VectorXd c(n), lo(n), hi(n);
    for (int i = 0; i < n; ++i) {
      c[i] = 2.0 * u(rng);
      lo[i] = -0.5 + 0.4 * u(rng);
      hi[i] = lo[i] + 0.05 + std::abs(u(rng));
    }
    BoxQpSolver qp(n);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    const BoxQpReport rep = qp.solve(H, c, lo, hi, x, 100);
    ASSERT_EQ(rep.status, BoxQpStatus::Optimal) << "trial " << trial;
    const Eigen::VectorXd g = H * x + c;
    for (int i = 0; i < n; ++i) {
      ASSERT_GE(x[i], lo[i]);
      ASSERT_LE(x[i], hi[i]);
      if (x[i] > lo[i] && x[i] < hi[i]) {
        EXPECT_NEAR(g[i], 0.0, 1e-8) << "trial " << trial;
      }
      if (x[i] == lo[i]) {
        EXPECT_GE(g[i], -1e-8);
      }
      if (x[i] == hi[i]) {
        EXPECT_LE(g[i], 1e-8);
      }
    }
    EXPECT_NEAR(objective(H, c, x), bruteForce(H, c, lo, hi), 1e-9) << "trial " << trial;
  }
}

TEST(BoxQpSolver, RejectsEmptyProblem) { EXPECT_THROW(BoxQpSolver(0), std::invalid_argument); }

}  // namespace
}  // namespace surgical_sim::core
