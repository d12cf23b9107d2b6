#include "surgical_sim/core/contact/projected_gauss_seidel.h"

#include <algorithm>
#include <cmath>

namespace surgical_sim::core {

double lcpMinMapResidual(const Eigen::Ref<const Eigen::MatrixXd>& W,
                         const Eigen::Ref<const Eigen::VectorXd>& q,
                         const Eigen::Ref<const Eigen::VectorXd>& lambda) {
  double residual = 0.0;
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    if (!(W(i, i) > 0.0)) continue;
    const double w = q[i] + W.row(i).dot(lambda);  // reads only the columns of lambda_j != 0
    residual = std::max(residual, std::abs(std::min(lambda[i] * W(i, i), w)));
  }
  return residual;
}

PgsReport solveLcpProjectedGaussSeidel(const Eigen::Ref<const Eigen::MatrixXd>& W,
                                       const Eigen::Ref<const Eigen::VectorXd>& q,
                                       int max_iterations, double tolerance,
                                       Eigen::Ref<Eigen::VectorXd> lambda) {
  PgsReport report;
  const Eigen::Index m = q.size();
  for (Eigen::Index i = 0; i < m; ++i) {
    if (!(W(i, i) > 0.0) || !(lambda[i] > 0.0)) lambda[i] = 0.0;
  }
  for (int sweep = 1; sweep <= max_iterations; ++sweep) {
    for (Eigen::Index i = 0; i < m; ++i) {
      if (!(W(i, i) > 0.0)) continue;
      const double w = q[i] + W.row(i).dot(lambda);  // reads only the columns of lambda_j != 0
      lambda[i] = std::max(0.0, lambda[i] - w / W(i, i));
    }
    report.iterations = sweep;
    report.residual = lcpMinMapResidual(W, q, lambda);
    if (report.residual <= tolerance) {
      report.converged = true;
      break;
    }
  }
  return report;
}

}  // namespace surgical_sim::core
