#include "surgical_sim/core/solve/warped_cholesky_pcg_solver.h"

namespace surgical_sim::core {

WarpedCholeskyPcgSolver::WarpedCholeskyPcgSolver(const PcgSettings& settings)
    : settings_(settings) {
  validatePcgSettings(settings);
}

std::string WarpedCholeskyPcgSolver::name() const { return "pcg_cholesky_warped"; }

void WarpedCholeskyPcgSolver::setLinearizationState(const TissueModel& model,
                                                    const Eigen::VectorXd& x) {
  state_announced_ = model.nodeRotations(x, state_rotations_);
}

void WarpedCholeskyPcgSolver::analyzePattern(const Eigen::SparseMatrix<double>& A) {
  matrix_ = A;
  matrix_.makeCompressed();
  const Eigen::Index n = A.rows();
  max_iterations_ = pcgIterationCap(settings_, n);
  work_.resize(n);
  rotated_rhs_.setZero(n);
  rotated_solution_.setZero(n);
  cholesky_.analyzePattern(matrix_);
  calls_since_refresh_ = 0;
  cholesky_valid_ = false;
  factor_has_rotations_ = false;
  warped_ = false;
  factorized_ = false;
}

bool WarpedCholeskyPcgSolver::factorize(const Eigen::SparseMatrix<double>& A) {
  factorized_ = false;
  warped_ = false;
  const bool rotations =
      state_announced_ && 3 * static_cast<Eigen::Index>(state_rotations_.size()) == A.rows();
  state_announced_ = false;
  if (!copyValuesOfSamePattern(A, matrix_)) return false;
  if (!cholesky_valid_ || calls_since_refresh_ >= settings_.refresh_interval) {
    calls_since_refresh_ = 0;
    cholesky_valid_ = cholesky_.factorize(matrix_);
    ++factorizations_;
    factor_has_rotations_ = rotations;
    if (rotations) factor_rotations_ = state_rotations_;
  } else if (rotations && factor_has_rotations_) {
    warp_.resize(state_rotations_.size());
    for (size_t i = 0; i < warp_.size(); ++i) {
      warp_[i].noalias() = state_rotations_[i] * factor_rotations_[i].transpose();
    }
    warped_ = true;
  }
  ++calls_since_refresh_;
  factorized_ = cholesky_valid_;
  return factorized_;
}

bool WarpedCholeskyPcgSolver::applyPreconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  if (!warped_) return cholesky_.precondition(r, z);
  for (size_t i = 0; i < warp_.size(); ++i) {
    const Eigen::Index k = 3 * static_cast<Eigen::Index>(i);
    rotated_rhs_.segment<3>(k).noalias() = warp_[i].transpose() * r.segment<3>(k);
  }
  if (!cholesky_.precondition(rotated_rhs_, rotated_solution_)) return false;
  for (size_t i = 0; i < warp_.size(); ++i) {
    const Eigen::Index k = 3 * static_cast<Eigen::Index>(i);
    z.segment<3>(k).noalias() = warp_[i] * rotated_solution_.segment<3>(k);
  }
  return true;
}

LinearSolveReport WarpedCholeskyPcgSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!factorized_) return {};
  return preconditionedConjugateGradient(
      matrix_, b, x, max_iterations_, settings_.relative_tolerance,
      [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) { return applyPreconditioner(r, z); },
      work_);
}

}  // namespace surgical_sim::core
