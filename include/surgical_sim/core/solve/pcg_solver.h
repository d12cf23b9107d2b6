#pragma once

#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <optional>
#include <string>
#include <vector>

#include "surgical_sim/core/solve/block_jacobi.h"
#include "surgical_sim/core/solve/cholmod_solver.h"
#include "surgical_sim/core/solve/conjugate_gradient.h"
#include "surgical_sim/core/solve/linear_solver.h"
#include "surgical_sim/core/solve/local_schwarz_correction.h"

namespace surgical_sim::core {

/// Preconditioner of PcgSolver.
enum class PcgPreconditioner {
  Jacobi,              ///< inverse diagonal ("pcg_jacobi")
  BlockJacobi,         ///< inverted 3x3 node blocks of the diagonal ("pcg_block_jacobi")
  IncompleteCholesky,  ///< Eigen::IncompleteCholesky with AMD ordering ("pcg_ichol")
  /// CHOLMOD factor of an earlier matrix, refreshed every refresh_interval factorize() calls
  /// ("pcg_cholesky_reuse"): the real-time strategy (a triangular solve is far cheaper than a
  /// refactorization, and the stiffness changes little between steps). Applied through a
  /// single-precision copy (CholmodPreconditioning::SinglePrecision): a fresh factor then needs 2
  /// iterations instead of 1 to reach 1e-10, an older one as many as with the double factor.
  CholeskyReuse,
  /// The CholeskyReuse factor warped by per-node rotations ("pcg_cholesky_warped"): a co-rotated
  /// stiffness at x is close to W K_f W^T, K_f the matrix of the factor's state x_f and W =
  /// blockdiag(R_i(x) R_i(x_f)^T) (TissueModel::nodeRotations of the states announced by
  /// setLinearizationState(); lumped masses are rotation invariant), so z = W L^-T L^-1 W^T r
  /// stays a good preconditioner while the body turns. A factorize() without an announced state
  /// with rotations (or of another node count), or whose factor was taken without, is not warped
  /// (as CholeskyReuse).
  CholeskyWarped,
};

/// Settings of PcgSolver (numerical, not physical: the defaults are documented choices).
struct PcgSettings {
  /// CG iteration limit [-], >= 1. Unset: sized from the problem, pcgIterationCap().
  std::optional<int> max_iterations;
  double relative_tolerance = 1e-10;  ///< stop when |b - A x| <= tol |b| [-], in (0, 1)
  /// CholeskyReuse, CholeskyWarped: refactorize every this many factorize() calls [-], >= 1
  int refresh_interval = 10;
  /// CholeskyReuse, CholeskyWarped: also refactorize earlier, at a factorize() whose previous call
  /// (that factorize(), the solves after it and a pattern analysis before this one) took longer, in
  /// wall time, than the mean call since the last refactorization, that refactorization included.
  /// For costs that grow with the factor's age (iterations, a growing local correction after cuts)
  /// this keeps the mean cost per call near its least; the refresh points then depend on the
  /// machine's timing.
  bool adaptive_refresh = false;
};

/// kMinSizedPcgIterations [-]: the smallest iteration limit pcgIterationCap() gives.
inline constexpr int kMinSizedPcgIterations = 1000;

/// The iteration limit of a CG solve of an n x n system: settings.max_iterations if set, else
/// max(kMinSizedPcgIterations, n) (in exact arithmetic CG ends within n iterations; the floor
/// leaves room for round-off on small, ill-conditioned systems).
int pcgIterationCap(const PcgSettings& settings, Eigen::Index n);

/// Throws std::invalid_argument naming "solver.max_iterations", "solver.relative_tolerance" or
/// "solver.refresh_interval" with its range if a setting is out of range.
void validatePcgSettings(const PcgSettings& settings);

/// Preconditioned conjugate gradient for symmetric positive-definite sparse matrices.
///
/// All work vectors are allocated in analyzePattern() (CholeskyWarped: the rotations in the first
/// setLinearizationState()); solve() allocates nothing. factorize() copies the matrix values (the
/// pattern must be the analysed one) and builds the preconditioner.
/// Not copyable or movable.
class PcgSolver final : public LinearSolver {
 public:
  /// @throws std::invalid_argument if settings are out of range (see validatePcgSettings).
  PcgSolver(PcgPreconditioner preconditioner, const PcgSettings& settings);
  PcgSolver(const PcgSolver&) = delete;
  PcgSolver& operator=(const PcgSolver&) = delete;
  PcgSolver(PcgSolver&&) = delete;
  PcgSolver& operator=(PcgSolver&&) = delete;

  /// "pcg_jacobi", "pcg_block_jacobi", "pcg_ichol", "pcg_cholesky_reuse" or "pcg_cholesky_warped".
  std::string name() const override;
  /// CholeskyWarped: stores model's node rotations at x for the next factorize(); otherwise
  /// ignored.
  void setLinearizationState(const TissueModel& model, const Eigen::VectorXd& x) override;
  /// Stores A's pattern, sizes all work vectors, analyses the preconditioner's pattern.
  /// CholeskyReuse, CholeskyWarped with a factor of the same size and another pattern (a cut of a
  /// model whose DOFs stay, e.g. EfgVolumeCutter): the factor is kept, not re-analysed. Until its
  /// refresh is due (refresh_interval, adaptive_refresh) it preconditions the
  /// new pattern through a LocalSchwarzCorrection on the unknowns whose pattern changed
  /// (changedPatternUnknowns() with kLocalRings rings); the refresh re-analyses the new pattern,
  /// keeping the fill-reducing ordering (CholmodSolver::analyzeChangedPattern).
  /// The same pattern, or a change on more than half the unknowns, is analysed afresh.
  void analyzePattern(const Eigen::SparseMatrix<double>& A) override;
  /// Copies A's values and builds the preconditioner. Returns false if the pattern differs, a
  /// (block) diagonal is not positive definite or the preconditioner factorization failed.
  bool factorize(const Eigen::SparseMatrix<double>& A) override;
  /// CG iterations on A x = b from the initial guess x (size n). ok when the relative residual
  /// reaches relative_tolerance within pcgIterationCap(settings, n) iterations; false on breakdown
  /// (p^T A p <= 0, NaN) or at the cap (then capped). With a factor of an older pattern (see
  /// analyzePattern()), a solve that fails within kStaleIterations iterations refactorizes A
  /// (re-analysed) and continues from its last iterate (reported iterations: both solves).
  LinearSolveReport solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;

  /// Cholesky factorizations since construction (CholeskyReuse, CholeskyWarped; for tests and
  /// benchmarks).
  int choleskyFactorizations() const { return cholesky_factorizations_; }
  /// Symbolic analyses of the Cholesky preconditioner since construction (CholeskyReuse,
  /// CholeskyWarped; for tests and benchmarks).
  int choleskyAnalyses() const { return cholesky_analyses_; }
  /// Fresh fill-reducing orderings among them (a refresh of a changed pattern keeps the ordering:
  /// CholmodSolver::analyzeChangedPattern).
  int choleskyOrderings() const { return cholesky_.orderings(); }
  /// Rings of pattern neighbours around the changed unknowns of a kept factor's correction.
  static constexpr int kLocalRings = 1;
  /// Iteration budget of a solve with a factor of an older pattern before it refactorizes.
  static constexpr int kStaleIterations = 50;

 private:
  bool buildJacobi();
  bool buildIncompleteCholesky();
  /// Refactorizes when due (re-analysing a changed pattern); CholeskyWarped: stores the factor's
  /// rotations or sets the warp; a factor of an older pattern: factorizes the local correction.
  bool buildCholeskyReuse();
  /// True when the factor is due for a refresh (refresh_interval, adaptive_refresh); starts the
  /// timing of the current call.
  bool refreshDue();
  /// Analyses matrix_'s pattern and factorizes it (the refresh of buildCholeskyReuse()).
  void refactorizeCholesky(bool rotations);
  /// z = (warped) factor applied to r: the global part of a kept factor's correction.
  bool applyCholesky(const Eigen::VectorXd& r, Eigen::VectorXd& z);
  /// z = W L^-T L^-1 W^T r with the warp_ blocks.
  bool applyWarpedCholesky(const Eigen::VectorXd& r, Eigen::VectorXd& z);
  /// analyzePattern(), which times it for adaptive_refresh.
  void analyzeNewPattern(const Eigen::SparseMatrix<double>& A);
  /// The CG solve of solve(), which times it for adaptive_refresh.
  LinearSolveReport solveWithPreconditioner(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// z = P^-1 r. Returns false if the preconditioner application failed.
  bool applyPreconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z);

  PcgPreconditioner preconditioner_;
  PcgSettings settings_;
  int max_iterations_ = 0;  ///< pcgIterationCap of the analysed pattern
  Eigen::SparseMatrix<double> matrix_;
  CgWorkspace work_;
  Eigen::VectorXd scratch_;
  Eigen::VectorXd inverse_diagonal_;
  BlockJacobi block_jacobi_;
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>> incomplete_cholesky_;
  CholmodSolver cholesky_{CholmodOrdering::Metis, CholmodPreconditioning::SinglePrecision};
  int calls_since_refresh_ = 0;
  /// Wall time of the current call (the last factorize(), the solves after it and an
  /// analyzePattern() before the next factorize()) [s].
  double call_seconds_ = 0.0;
  /// Wall time of the calls since the last refactorization, before the current one [s].
  double cycle_seconds_ = 0.0;
  bool cholesky_valid_ = false;
  int cholesky_factorizations_ = 0;
  int cholesky_analyses_ = 0;
  /// The factor is of an older pattern than matrix_ (kept by analyzePattern()).
  bool stale_pattern_ = false;
  LocalSchwarzCorrection local_;        ///< on the changed unknowns while stale_pattern_
  PreconditionerApply cholesky_apply_;  ///< applyCholesky, the global part of local_
  bool factorized_ = false;
  // CholeskyWarped.
  std::vector<Eigen::Matrix3d> state_rotations_;   ///< of the last setLinearizationState()
  bool state_announced_ = false;                   ///< state_rotations_ are for the next factorize
  std::vector<Eigen::Matrix3d> factor_rotations_;  ///< at the factor's state
  bool factor_has_rotations_ = false;
  std::vector<Eigen::Matrix3d> warp_;  ///< W's blocks R_i(x) R_i(x_f)^T
  bool warped_ = false;                ///< the current preconditioner applies warp_
};

}  // namespace surgical_sim::core
