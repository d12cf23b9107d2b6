#include "surgical_sim/core/solve/conjugate_gradient.h"

#include <algorithm>
#include <cmath>

namespace surgical_sim::core {

void CgWorkspace::resize(Eigen::Index n) {
  residual.setZero(n);
  direction.setZero(n);
  product.setZero(n);
  preconditioned.setZero(n);
}

bool copyValuesOfSamePattern(const Eigen::SparseMatrix<double>& A,
                             Eigen::SparseMatrix<double>& into) {
  if (!A.isCompressed() || A.rows() != into.rows() || A.cols() != into.cols() ||
      A.nonZeros() != into.nonZeros()) {
    return false;
  }
  std::copy(A.valuePtr(), A.valuePtr() + A.nonZeros(), into.valuePtr());
  return true;
}

LinearSolveReport preconditionedConjugateGradient(const Eigen::SparseMatrix<double>& A,
                                                  const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                                  int max_iterations, double relative_tolerance,
                                                  const PreconditionerApply& precondition,
                                                  CgWorkspace& work) {
  LinearSolveReport report;
  if (b.size() != A.rows() || x.size() != b.size() || work.residual.size() != b.size()) {
    return report;
  }
  const double b_norm = b.norm();
  if (!std::isfinite(b_norm)) return report;
  if (b_norm == 0.0) {
    x.setZero();
    report.ok = true;
    return report;
  }
  if (!x.allFinite()) x.setZero();
  const double tolerance = relative_tolerance * b_norm;
  work.residual = b;
  work.residual.noalias() -= A * x;
  double residual_norm = work.residual.norm();
  if (residual_norm <= tolerance) {
    report.ok = true;
    report.relative_residual = residual_norm / b_norm;
    return report;
  }
  if (!precondition(work.residual, work.preconditioned)) return report;
  work.direction = work.preconditioned;
  double rz = work.residual.dot(work.preconditioned);
  for (int k = 1; k <= max_iterations; ++k) {
    work.product.noalias() = A * work.direction;
    const double curvature = work.direction.dot(work.product);
    if (!(curvature > 0.0) || !std::isfinite(curvature) || !std::isfinite(rz)) {
      report.iterations = k;
      report.relative_residual = residual_norm / b_norm;
      return report;
    }
    const double alpha = rz / curvature;
    x.noalias() += alpha * work.direction;
    work.residual.noalias() -= alpha * work.product;
    residual_norm = work.residual.norm();
    report.iterations = k;
    report.relative_residual = residual_norm / b_norm;
    if (!std::isfinite(residual_norm)) return report;
    if (residual_norm <= tolerance) {
      report.ok = true;
      return report;
    }
    if (!precondition(work.residual, work.preconditioned)) return report;
    const double rz_next = work.residual.dot(work.preconditioned);
    const double beta = rz_next / rz;
    rz = rz_next;
    work.direction = work.preconditioned + beta * work.direction;
  }
  report.capped = true;
  return report;
}

}  // namespace surgical_sim::core
