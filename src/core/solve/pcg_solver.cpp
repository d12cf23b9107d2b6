#include "surgical_sim/core/solve/pcg_solver.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

void validatePcgSettings(const PcgSettings& settings) {
  const double int_max = std::numeric_limits<int>::max();
  requireInRange("solver.max_iterations", settings.max_iterations, 1, int_max, "");
  requireInHalfOpenRange("solver.relative_tolerance", settings.relative_tolerance,
                         std::numeric_limits<double>::min(), 1.0, "");
  requireInRange("solver.refresh_interval", settings.refresh_interval, 1, int_max, "");
}

PcgSolver::PcgSolver(PcgPreconditioner preconditioner, const PcgSettings& settings)
    : preconditioner_(preconditioner), settings_(settings) {
  validatePcgSettings(settings);
}

std::string PcgSolver::name() const {
  switch (preconditioner_) {
    case PcgPreconditioner::Jacobi:
      return "pcg_jacobi";
    case PcgPreconditioner::BlockJacobi:
      return "pcg_block_jacobi";
    case PcgPreconditioner::IncompleteCholesky:
      return "pcg_ichol";
    case PcgPreconditioner::CholeskyReuse:
      return "pcg_cholesky_reuse";
  }
  return "pcg";
}

void PcgSolver::analyzePattern(const Eigen::SparseMatrix<double>& A) {
  matrix_ = A;
  matrix_.makeCompressed();
  const Eigen::Index n = A.rows();
  residual_.setZero(n);
  direction_.setZero(n);
  product_.setZero(n);
  preconditioned_.setZero(n);
  scratch_.setZero(n);
  inverse_diagonal_.resize(0);
  inverse_blocks_.clear();
  switch (preconditioner_) {
    case PcgPreconditioner::Jacobi:
      inverse_diagonal_.setZero(n);
      break;
    case PcgPreconditioner::BlockJacobi:
      inverse_blocks_.assign(static_cast<size_t>((n + 2) / 3), Eigen::Matrix3d::Zero());
      break;
    case PcgPreconditioner::IncompleteCholesky:
      incomplete_cholesky_.analyzePattern(matrix_);
      break;
    case PcgPreconditioner::CholeskyReuse:
      cholesky_.analyzePattern(matrix_);
      break;
  }
  calls_since_refresh_ = 0;
  cholesky_valid_ = false;
  factorized_ = false;
}

bool PcgSolver::factorize(const Eigen::SparseMatrix<double>& A) {
  factorized_ = false;
  if (!A.isCompressed() || A.rows() != matrix_.rows() || A.cols() != matrix_.cols() ||
      A.nonZeros() != matrix_.nonZeros()) {
    return false;
  }
  std::copy(A.valuePtr(), A.valuePtr() + A.nonZeros(), matrix_.valuePtr());
  switch (preconditioner_) {
    case PcgPreconditioner::Jacobi:
      factorized_ = buildJacobi();
      break;
    case PcgPreconditioner::BlockJacobi:
      factorized_ = buildBlockJacobi();
      break;
    case PcgPreconditioner::IncompleteCholesky:
      factorized_ = buildIncompleteCholesky();
      break;
    case PcgPreconditioner::CholeskyReuse:
      factorized_ = buildCholeskyReuse();
      break;
  }
  return factorized_;
}

bool PcgSolver::buildJacobi() {
  const Eigen::Index n = matrix_.rows();
  for (Eigen::Index j = 0; j < n; ++j) {
    double diagonal = 0.0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix_, j); it; ++it) {
      if (it.row() == j) diagonal = it.value();
    }
    if (!(diagonal > 0.0) || !std::isfinite(diagonal)) return false;
    inverse_diagonal_[j] = 1.0 / diagonal;
  }
  return true;
}

bool PcgSolver::buildBlockJacobi() {
  const Eigen::Index n = matrix_.rows();
  for (Eigen::Matrix3d& block : inverse_blocks_) block.setZero();
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix_, j); it; ++it) {
      if (it.row() / 3 == j / 3) {
        inverse_blocks_[static_cast<size_t>(j / 3)](it.row() % 3, j % 3) = it.value();
      }
    }
  }
  // A trailing partial block (n not a multiple of 3) gets identity in its unused slots.
  for (Eigen::Index k = n; k % 3 != 0; ++k) inverse_blocks_.back()(k % 3, k % 3) = 1.0;
  for (Eigen::Matrix3d& block : inverse_blocks_) {
    Eigen::LLT<Eigen::Matrix3d> llt(block);
    if (llt.info() != Eigen::Success) return false;
    block = llt.solve(Eigen::Matrix3d::Identity());
    if (!block.allFinite()) return false;
  }
  return true;
}

bool PcgSolver::buildIncompleteCholesky() {
  incomplete_cholesky_.factorize(matrix_);
  return incomplete_cholesky_.info() == Eigen::Success;
}

bool PcgSolver::buildCholeskyReuse() {
  if (!cholesky_valid_ || calls_since_refresh_ >= settings_.refresh_interval) {
    calls_since_refresh_ = 0;
    cholesky_valid_ = cholesky_.factorize(matrix_);
  }
  ++calls_since_refresh_;
  return cholesky_valid_;
}

bool PcgSolver::applyPreconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  switch (preconditioner_) {
    case PcgPreconditioner::Jacobi:
      z = inverse_diagonal_.cwiseProduct(r);
      return true;
    case PcgPreconditioner::BlockJacobi: {
      const Eigen::Index n = r.size();
      for (Eigen::Index start = 0, b = 0; start < n; start += 3, ++b) {
        const Eigen::Index m = std::min<Eigen::Index>(3, n - start);
        z.segment(start, m).noalias() =
            inverse_blocks_[static_cast<size_t>(b)].topLeftCorner(m, m) * r.segment(start, m);
      }
      return true;
    }
    case PcgPreconditioner::IncompleteCholesky: {
      // Same operations as IncompleteCholesky::solve, written out to avoid its temporaries:
      // z = P^-1 S L^-T L^-1 S P r.
      const auto& perm = incomplete_cholesky_.permutationP();
      const auto& scale = incomplete_cholesky_.scalingS();
      const auto& factor = incomplete_cholesky_.matrixL();
      if (perm.size() == r.size()) {
        scratch_.noalias() = perm * r;
      } else {
        scratch_ = r;
      }
      scratch_.array() *= scale.array();
      factor.triangularView<Eigen::Lower>().solveInPlace(scratch_);
      factor.adjoint().triangularView<Eigen::Upper>().solveInPlace(scratch_);
      scratch_.array() *= scale.array();
      if (perm.size() == r.size()) {
        z.noalias() = perm.inverse() * scratch_;
      } else {
        z = scratch_;
      }
      return true;
    }
    case PcgPreconditioner::CholeskyReuse:
      return cholesky_.solve(r, z).ok;
  }
  return false;
}

LinearSolveReport PcgSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  LinearSolveReport report;
  if (!factorized_ || b.size() != matrix_.rows() || x.size() != b.size()) return report;
  const double b_norm = b.norm();
  if (!std::isfinite(b_norm)) return report;
  if (b_norm == 0.0) {
    x.setZero();
    report.ok = true;
    return report;
  }
  if (!x.allFinite()) x.setZero();
  const double tolerance = settings_.relative_tolerance * b_norm;
  residual_ = b;
  residual_.noalias() -= matrix_ * x;
  double residual_norm = residual_.norm();
  if (residual_norm <= tolerance) {
    report.ok = true;
    report.relative_residual = residual_norm / b_norm;
    return report;
  }
  if (!applyPreconditioner(residual_, preconditioned_)) return report;
  direction_ = preconditioned_;
  double rz = residual_.dot(preconditioned_);
  for (int k = 1; k <= settings_.max_iterations; ++k) {
    product_.noalias() = matrix_ * direction_;
    const double curvature = direction_.dot(product_);
    if (!(curvature > 0.0) || !std::isfinite(curvature) || !std::isfinite(rz)) {
      report.iterations = k;
      report.relative_residual = residual_norm / b_norm;
      return report;
    }
    const double alpha = rz / curvature;
    x.noalias() += alpha * direction_;
    residual_.noalias() -= alpha * product_;
    residual_norm = residual_.norm();
    report.iterations = k;
    report.relative_residual = residual_norm / b_norm;
    if (!std::isfinite(residual_norm)) return report;
    if (residual_norm <= tolerance) {
      report.ok = true;
      return report;
    }
    if (!applyPreconditioner(residual_, preconditioned_)) return report;
    const double rz_next = residual_.dot(preconditioned_);
    const double beta = rz_next / rz;
    rz = rz_next;
    direction_ = preconditioned_ + beta * direction_;
  }
  return report;
}

}  // namespace surgical_sim::core
