#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>

#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// Result of one linear solve.
struct LinearSolveReport {
  bool ok = false;                 ///< solved: x finite, relative_residual within the tolerance
  int iterations = 0;              ///< 1 for a direct solve
  double relative_residual = 0.0;  ///< |b - A x| / |b|
  /// An iterative solve stopped at its iteration cap without breakdown: x is the last (finite)
  /// iterate, an inexact solution; ok is false.
  bool capped = false;
};

/// Symmetric positive-definite sparse solver. Usage per topology: analyzePattern once; then per
/// step factorize (numeric) and solve any number of right-hand sides.
class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  /// "cholmod", "pcg_jacobi", "pcg_block_jacobi", "pcg_ichol", "pcg_cholesky_reuse",
  /// "pcg_cholesky_background", "pcg_cholesky_warped".
  virtual std::string name() const = 0;
  /// Symbolic analysis for A's pattern. Call again only when the pattern changes (topology).
  virtual void analyzePattern(const Eigen::SparseMatrix<double>& A) = 0;
  /// analyzePattern() of a changed pattern of the same size (a cut added or removed couplings): a
  /// solver may keep what still holds (CholmodSolver: the fill-reducing ordering). Default:
  /// analyzePattern().
  virtual void analyzeChangedPattern(const Eigen::SparseMatrix<double>& A) { analyzePattern(A); }
  /// Announces the state of the matrix the next factorize() receives: model at positions x (size
  /// 3n, the matrix 3n x 3n). Solvers whose preconditioner uses the model (pcg_cholesky_warped:
  /// node rotations) read it here; the default ignores it. Allocation-free after the first call.
  virtual void setLinearizationState(const TissueModel& /*model*/, const Eigen::VectorXd& /*x*/) {}
  /// Numeric set-up (factorization or preconditioner) for A with the analysed pattern.
  /// Returns false if A is not positive definite or set-up failed.
  virtual bool factorize(const Eigen::SparseMatrix<double>& A) = 0;
  /// Solves A x = b. For iterative solvers x on entry is the initial guess. Allocation-free.
  virtual LinearSolveReport solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) = 0;
};

}  // namespace surgical_sim::core
