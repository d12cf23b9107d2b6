#include "surgical_sim/core/robot/box_qp_solver.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace surgical_sim::core {

BoxQpSolver::BoxQpSolver(int size) {
  if (size < 1)
    throw std::invalid_argument("box_qp.size = " + std::to_string(size) +
                                " is out of range: must be >= 1");
  state_.resize(size);
  free_.reserve(size);
  chol_.resize(size, size);
  gradient_.resize(size);
  step_.resize(size);
  rhs_.resize(size);
}

BoxQpReport BoxQpSolver::solve(const Eigen::MatrixXd& H, const Eigen::VectorXd& c,
                               const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                               Eigen::VectorXd& x, int max_iterations) {
  const int n = static_cast<int>(state_.size());
  BoxQpReport report;
  for (int i = 0; i < n; ++i) {
    x[i] = std::min(std::max(x[i], lo[i]), hi[i]);
    state_[i] = x[i] <= lo[i] ? Bound::Lower : (x[i] >= hi[i] ? Bound::Upper : Bound::Free);
  }
  const double h_scale = H.diagonal().cwiseAbs().maxCoeff() + std::numeric_limits<double>::min();
  for (report.iterations = 1; report.iterations <= max_iterations; ++report.iterations) {
    gradient_.noalias() = H * x;
    gradient_ += c;
    free_.clear();
    for (int i = 0; i < n; ++i)
      if (state_[i] == Bound::Free) free_.push_back(i);
    const int m = static_cast<int>(free_.size());
    // Newton step on the free variables: H_FF p = -g_F (in-place Cholesky of H_FF).
    for (int a = 0; a < m; ++a)
      for (int b = 0; b <= a; ++b) {
        double s = H(free_[a], free_[b]);
        for (int k = 0; k < b; ++k) s -= chol_(a, k) * chol_(b, k);
        if (a == b) {
          if (!(s > 1e-14 * h_scale)) {
            report.status = BoxQpStatus::NotConvex;
            return report;
          }
          chol_(a, a) = std::sqrt(s);
        } else {
          chol_(a, b) = s / chol_(b, b);
        }
      }
    for (int a = 0; a < m; ++a) {
      double s = -gradient_[free_[a]];
      for (int k = 0; k < a; ++k) s -= chol_(a, k) * rhs_[k];
      rhs_[a] = s / chol_(a, a);
    }
    for (int a = m - 1; a >= 0; --a) {
      double s = rhs_[a];
      for (int k = a + 1; k < m; ++k) s -= chol_(k, a) * step_[k];
      step_[a] = s / chol_(a, a);
    }
    // Ratio test against the bounds of the free variables.
    double alpha = 1.0;
    int blocking = -1;
    bool blocking_lower = false;
    for (int a = 0; a < m; ++a) {
      const int i = free_[a];
      const double p = step_[a];
      if (p < 0.0 && x[i] + p < lo[i]) {
        const double t = (lo[i] - x[i]) / p;
        if (t < alpha) alpha = t, blocking = i, blocking_lower = true;
      } else if (p > 0.0 && x[i] + p > hi[i]) {
        const double t = (hi[i] - x[i]) / p;
        if (t < alpha) alpha = t, blocking = i, blocking_lower = false;
      }
    }
    for (int a = 0; a < m; ++a) x[free_[a]] += alpha * step_[a];
    if (blocking >= 0) {
      state_[blocking] = blocking_lower ? Bound::Lower : Bound::Upper;
      x[blocking] = blocking_lower ? lo[blocking] : hi[blocking];
      continue;
    }
    // Full Newton step taken: the free subproblem is solved. Check the bound multipliers.
    gradient_.noalias() = H * x;
    gradient_ += c;
    int release = -1;
    double worst = 0.0;
    for (int i = 0; i < n; ++i) {
      const double mu = state_[i] == Bound::Lower   ? gradient_[i]
                        : state_[i] == Bound::Upper ? -gradient_[i]
                                                    : 0.0;
      const double scaled = mu / std::sqrt(H(i, i) + std::numeric_limits<double>::min());
      if (scaled < worst) worst = scaled, release = i;
    }
    const double g_scale = (H.cwiseAbs() * x.cwiseAbs()).norm() + c.norm();
    if (release < 0 || -worst * std::sqrt(H(release, release)) <= 1e-13 * g_scale) {
      report.status = BoxQpStatus::Optimal;
      return report;
    }
    state_[release] = Bound::Free;
  }
  report.iterations = max_iterations;
  report.status = BoxQpStatus::MaxIterations;
  return report;
}

}  // namespace surgical_sim::core
