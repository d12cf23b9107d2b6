#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "surgical_sim/core/solve/cholmod_solver.h"
#include "surgical_sim/core/solve/conjugate_gradient.h"
#include "surgical_sim/core/solve/linear_solver.h"
#include "surgical_sim/core/solve/pcg_solver.h"

namespace surgical_sim::core {

/// PCG preconditioned by a CHOLMOD factor of an earlier matrix, warped by per-node rotations
/// ("pcg_cholesky_warped"): a co-rotated stiffness at x is close to W K_f W^T, K_f the stiffness
/// at the factor's state x_f and W = blockdiag(R_i(x) R_i(x_f)^T) (TissueModel::nodeRotations;
/// lumped masses are rotation invariant), so P^-1 r = W L^-T L^-1 W^T r stays a good
/// preconditioner under large rotations, where the plain reused factor (pcg_cholesky_reuse)
/// needs many more iterations.
///
/// Factor: refactorized every settings.refresh_interval factorize() calls (and on the first call
/// after analyzePattern()), applied through a single-precision copy (CholmodPreconditioning::
/// SinglePrecision); the residual and iterates stay in double. Rotations: those of the last
/// setLinearizationState() before each factorize(); a factorize() without one (or with a model
/// that defines no rotations, or whose node count is not the matrix's) uses no warp until the next
/// refactorization with rotations, i.e. behaves as pcg_cholesky_reuse.
///
/// Accuracy: same tolerance semantics as PcgSolver (ok when |b - A x| <= tol |b| within
/// pcgIterationCap; a solve at the cap reports capped). Work vectors are allocated in
/// analyzePattern() and the first setLinearizationState(); solve() allocates nothing. Not copyable
/// or movable.
class WarpedCholeskyPcgSolver final : public LinearSolver {
 public:
  /// @throws std::invalid_argument if settings are out of range (see validatePcgSettings).
  explicit WarpedCholeskyPcgSolver(const PcgSettings& settings);
  WarpedCholeskyPcgSolver(const WarpedCholeskyPcgSolver&) = delete;
  WarpedCholeskyPcgSolver& operator=(const WarpedCholeskyPcgSolver&) = delete;
  WarpedCholeskyPcgSolver(WarpedCholeskyPcgSolver&&) = delete;
  WarpedCholeskyPcgSolver& operator=(WarpedCholeskyPcgSolver&&) = delete;

  /// Returns "pcg_cholesky_warped".
  std::string name() const override;
  /// Stores model's node rotations at x for the next factorize().
  void setLinearizationState(const TissueModel& model, const Eigen::VectorXd& x) override;
  /// Stores A's pattern, sizes the work vectors and analyses the factor's pattern.
  void analyzePattern(const Eigen::SparseMatrix<double>& A) override;
  /// Copies A's values, refactorizes when due, and sets the warp from the announced rotations.
  /// Returns false if the pattern differs or the factorization failed.
  bool factorize(const Eigen::SparseMatrix<double>& A) override;
  /// PCG on A x = b from the initial guess x (size n).
  LinearSolveReport solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;

  /// Number of factorizations since construction (for tests and benchmarks).
  int factorizations() const { return factorizations_; }

 private:
  /// z = W L^-T L^-1 W^T r (without the warp: the factor alone).
  bool applyPreconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z);

  PcgSettings settings_;
  int max_iterations_ = 0;  ///< pcgIterationCap of the analysed pattern
  Eigen::SparseMatrix<double> matrix_;
  CgWorkspace work_;
  CholmodSolver cholesky_{CholmodOrdering::Metis, CholmodPreconditioning::SinglePrecision};
  std::vector<Eigen::Matrix3d> state_rotations_;   ///< of the last setLinearizationState()
  bool state_announced_ = false;                   ///< state_rotations_ are for the next factorize
  std::vector<Eigen::Matrix3d> factor_rotations_;  ///< at the factor's state
  bool factor_has_rotations_ = false;
  std::vector<Eigen::Matrix3d> warp_;  ///< W's blocks R_i(x) R_i(x_f)^T
  bool warped_ = false;
  Eigen::VectorXd rotated_rhs_, rotated_solution_;
  int calls_since_refresh_ = 0;
  bool cholesky_valid_ = false;
  bool factorized_ = false;
  int factorizations_ = 0;
};

}  // namespace surgical_sim::core
