#include "surgical_sim/core/solve/pcg_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

void validatePcgSettings(const PcgSettings& settings) {
  const double int_max = std::numeric_limits<int>::max();
  if (settings.max_iterations) {
    requireInRange("solver.max_iterations", *settings.max_iterations, 1, int_max, "");
  }
  requireInHalfOpenRange("solver.relative_tolerance", settings.relative_tolerance,
                         std::numeric_limits<double>::min(), 1.0, "");
  requireInRange("solver.refresh_interval", settings.refresh_interval, 1, int_max, "");
}

int pcgIterationCap(const PcgSettings& settings, Eigen::Index n) {
  if (settings.max_iterations) return *settings.max_iterations;
  return static_cast<int>(std::min<Eigen::Index>(std::max<Eigen::Index>(kMinSizedPcgIterations, n),
                                                 std::numeric_limits<int>::max()));
}

PcgSolver::PcgSolver(PcgPreconditioner preconditioner, const PcgSettings& settings)
    : preconditioner_(preconditioner), settings_(settings) {
  validatePcgSettings(settings);
  cholesky_apply_ = [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    return applyCholesky(r, z);
  };
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
    case PcgPreconditioner::CholeskyWarped:
      return "pcg_cholesky_warped";
  }
  return "pcg";
}

void PcgSolver::setLinearizationState(const TissueModel& model, const Eigen::VectorXd& x) {
  if (preconditioner_ == PcgPreconditioner::CholeskyWarped) {
    state_announced_ = model.nodeRotations(x, state_rotations_);
  }
}

void PcgSolver::analyzePattern(const Eigen::SparseMatrix<double>& A) {
  timed(call_seconds_, [&] { analyzeNewPattern(A); });
}

void PcgSolver::analyzeNewPattern(const Eigen::SparseMatrix<double>& A) {
  const bool cholesky = preconditioner_ == PcgPreconditioner::CholeskyReuse ||
                        preconditioner_ == PcgPreconditioner::CholeskyWarped;
  if (cholesky && cholesky_valid_ && A.rows() == matrix_.rows() && A.cols() == matrix_.cols()) {
    // Same unknowns, changed pattern: keep the factor, correct it locally where it changed.
    Eigen::SparseMatrix<double> pattern = A;
    pattern.makeCompressed();
    std::vector<int> unknowns =
        changedPatternUnknowns(pattern, cholesky_.analysedMatrix(), kLocalRings);
    if (!unknowns.empty() && static_cast<Eigen::Index>(unknowns.size()) <= pattern.rows() / 2) {
      matrix_ = std::move(pattern);
      local_.setUnknowns(matrix_, std::move(unknowns));
      stale_pattern_ = true;
      warped_ = false;
      factorized_ = false;
      return;
    }
  }
  matrix_ = A;
  matrix_.makeCompressed();
  const Eigen::Index n = A.rows();
  max_iterations_ = pcgIterationCap(settings_, n);
  work_.resize(n);
  scratch_.setZero(n);
  inverse_diagonal_.resize(0);
  block_jacobi_.resize(0, 0);
  switch (preconditioner_) {
    case PcgPreconditioner::Jacobi:
      inverse_diagonal_.setZero(n);
      break;
    case PcgPreconditioner::BlockJacobi:
      block_jacobi_.resize(0, n);
      break;
    case PcgPreconditioner::IncompleteCholesky:
      incomplete_cholesky_.analyzePattern(matrix_);
      break;
    case PcgPreconditioner::CholeskyReuse:
    case PcgPreconditioner::CholeskyWarped:
      cholesky_.analyzePattern(matrix_);
      ++cholesky_analyses_;
      break;
  }
  calls_since_refresh_ = 0;
  cholesky_valid_ = false;
  stale_pattern_ = false;
  local_.setUnknowns(matrix_, {});
  factor_has_rotations_ = false;
  warped_ = false;
  factorized_ = false;
}

bool PcgSolver::factorize(const Eigen::SparseMatrix<double>& A) {
  const Stopwatch watch;
  factorized_ = false;
  if (!copyValuesOfSamePattern(A, matrix_)) return false;
  switch (preconditioner_) {
    case PcgPreconditioner::Jacobi:
      factorized_ = buildJacobi();
      break;
    case PcgPreconditioner::BlockJacobi:
      factorized_ = block_jacobi_.build(matrix_);
      break;
    case PcgPreconditioner::IncompleteCholesky:
      factorized_ = buildIncompleteCholesky();
      break;
    case PcgPreconditioner::CholeskyReuse:
    case PcgPreconditioner::CholeskyWarped:
      factorized_ = buildCholeskyReuse();
      break;
  }
  state_announced_ = false;
  call_seconds_ += watch.seconds();
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

bool PcgSolver::buildIncompleteCholesky() {
  incomplete_cholesky_.factorize(matrix_);
  return incomplete_cholesky_.info() == Eigen::Success;
}

bool PcgSolver::buildCholeskyReuse() {
  const bool rotations =
      state_announced_ && 3 * static_cast<Eigen::Index>(state_rotations_.size()) == matrix_.rows();
  warped_ = false;
  if (refreshDue()) {
    refactorizeCholesky(rotations);
  } else if (rotations && factor_has_rotations_) {
    warp_.resize(state_rotations_.size());
    for (size_t i = 0; i < warp_.size(); ++i) {
      warp_[i].noalias() = state_rotations_[i] * factor_rotations_[i].transpose();
    }
    warped_ = true;
  }
  ++calls_since_refresh_;
  if (cholesky_valid_ && stale_pattern_ && local_.active()) return local_.factorize(matrix_);
  return cholesky_valid_;
}

bool PcgSolver::refreshDue() {
  const double previous = call_seconds_;
  call_seconds_ = 0.0;
  cycle_seconds_ += previous;
  if (!cholesky_valid_ || calls_since_refresh_ >= settings_.refresh_interval) return true;
  return settings_.adaptive_refresh && previous * calls_since_refresh_ > cycle_seconds_;
}

void PcgSolver::refactorizeCholesky(bool rotations) {
  if (stale_pattern_ || cholesky_.analysedMatrix().rows() != matrix_.rows()) {
    cholesky_.analyzeChangedPattern(matrix_);
    ++cholesky_analyses_;
    stale_pattern_ = false;
    local_.setUnknowns(matrix_, {});
  }
  calls_since_refresh_ = 0;
  cycle_seconds_ = 0.0;
  cholesky_valid_ = cholesky_.factorize(matrix_);
  ++cholesky_factorizations_;
  factor_has_rotations_ = rotations;
  if (rotations) factor_rotations_ = state_rotations_;
}

bool PcgSolver::applyCholesky(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  return warped_ ? applyWarpedCholesky(r, z) : cholesky_.precondition(r, z);
}

bool PcgSolver::applyWarpedCholesky(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  for (size_t i = 0; i < warp_.size(); ++i) {
    const Eigen::Index k = 3 * static_cast<Eigen::Index>(i);
    z.segment<3>(k).noalias() = warp_[i].transpose() * r.segment<3>(k);
  }
  if (!cholesky_.precondition(z, scratch_)) return false;
  for (size_t i = 0; i < warp_.size(); ++i) {
    const Eigen::Index k = 3 * static_cast<Eigen::Index>(i);
    z.segment<3>(k).noalias() = warp_[i] * scratch_.segment<3>(k);
  }
  return true;
}

bool PcgSolver::applyPreconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  switch (preconditioner_) {
    case PcgPreconditioner::Jacobi:
      z = inverse_diagonal_.cwiseProduct(r);
      return true;
    case PcgPreconditioner::BlockJacobi:
      block_jacobi_.apply(r, z);
      return true;
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
    case PcgPreconditioner::CholeskyWarped:
      if (stale_pattern_ && local_.active()) return local_.apply(matrix_, r, z, cholesky_apply_);
      return applyCholesky(r, z);
  }
  return false;
}

LinearSolveReport PcgSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  return timed(call_seconds_, [&] { return solveWithPreconditioner(b, x); });
}

LinearSolveReport PcgSolver::solveWithPreconditioner(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!factorized_) return {};
  const PreconditionerApply precondition = [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    return applyPreconditioner(r, z);
  };
  if (!stale_pattern_) {
    return preconditionedConjugateGradient(matrix_, b, x, max_iterations_,
                                           settings_.relative_tolerance, precondition, work_);
  }
  LinearSolveReport report =
      preconditionedConjugateGradient(matrix_, b, x, std::min(max_iterations_, kStaleIterations),
                                      settings_.relative_tolerance, precondition, work_);
  if (report.ok) return report;
  // The kept factor does not precondition this matrix well enough: refactorize it.
  const int first_iterations = report.iterations;
  if (!x.allFinite()) x.setZero();
  refactorizeCholesky(false);
  warped_ = false;
  factorized_ = cholesky_valid_;
  if (!factorized_) return report;
  report = preconditionedConjugateGradient(matrix_, b, x, max_iterations_,
                                           settings_.relative_tolerance, precondition, work_);
  report.iterations += first_iterations;
  return report;
}

}  // namespace surgical_sim::core
