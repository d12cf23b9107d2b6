#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Outcome of a projected Gauss-Seidel solve.
struct PgsReport {
  int iterations = 0;      ///< sweeps performed
  double residual = 0.0;   ///< max_i |min(lambda_i W_ii, q_i + (W lambda)_i)| [m]
  bool converged = false;  ///< residual <= tolerance
};

/// LCP min-map residual max_i |min(lambda_i W_ii, (q + W lambda)_i)| [m] over rows with W_ii > 0.
double lcpMinMapResidual(const Eigen::Ref<const Eigen::MatrixXd>& W,
                         const Eigen::Ref<const Eigen::VectorXd>& q,
                         const Eigen::Ref<const Eigen::VectorXd>& lambda);

/// Projected Gauss-Seidel for the linear complementarity problem
///   0 <= lambda  _|_  q + W lambda >= 0,
/// W m x m symmetric positive semi-definite (contact compliance [m/N]), q the free gaps [m],
/// lambda the multipliers [N]. Sweeps lambda_i <- max(0, lambda_i - (q + W lambda)_i / W_ii)
/// until the min-map residual max_i |min(lambda_i W_ii, (q + W lambda)_i)| <= tolerance [m] or
/// max_iterations sweeps. Rows with W_ii <= 0 (unconstrainable) get lambda_i = 0.
/// lambda on entry is the warm start (negative entries are projected). Stateless, allocation-free.
PgsReport solveLcpProjectedGaussSeidel(const Eigen::Ref<const Eigen::MatrixXd>& W,
                                       const Eigen::Ref<const Eigen::VectorXd>& q,
                                       int max_iterations, double tolerance,
                                       Eigen::Ref<Eigen::VectorXd> lambda);

}  // namespace surgical_sim::core
