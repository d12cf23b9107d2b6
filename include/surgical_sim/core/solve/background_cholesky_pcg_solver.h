#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "surgical_sim/core/solve/block_jacobi.h"
#include "surgical_sim/core/solve/cholmod_solver.h"
#include "surgical_sim/core/solve/conjugate_gradient.h"
#include "surgical_sim/core/solve/linear_solver.h"
#include "surgical_sim/core/solve/local_schwarz_correction.h"
#include "surgical_sim/core/solve/pcg_solver.h"

namespace surgical_sim::core {

/// PCG preconditioned by a CHOLMOD factor of an earlier matrix that a worker thread refreshes in
/// the background ("pcg_cholesky_background"): the real-time variant of pcg_cholesky_reuse, whose
/// periodic refactorization and re-analysis after a topology change stall the step.
///
/// Refresh: a refresh is due every settings.refresh_interval factorize() calls, when a solve
/// needed more than kRefreshIterations PCG iterations, and while the factor is not of the
/// analysed pattern. When one is due and the worker is idle, factorize() hands it a copy of the
/// matrix and returns at once; the main thread keeps the current factor. The worker's factor
/// (own CholmodSolver, own cholmod_common, BLAS/OpenMP limited to one thread: on 2 cores, a
/// two-thread BLAS in the worker doubled the mean step time at 6.6k unknowns) is swapped in at
/// the start of the next factorize() - never in solve(), so the interim preconditioner below is
/// built once per matrix (adopting in solve() rebuilt it twice in some cutting steps) - if it is
/// of a newer matrix than the current one and has at most n rows. The worker also makes the
/// factor's single-precision copy (CholmodPreconditioning::SinglePrecision), which applies it.
///
/// Pattern change: analyzePattern() with a new pattern keeps a factor of n_old <= n_new rows,
/// assuming the first n_old unknowns keep their meaning (cutting appends nodes). Until the worker
/// delivers a factor of the new pattern (started by the next factorize()), the preconditioner is
/// G = blockdiag(old factor on the first n_old unknowns, 3x3 block-Jacobi of the new matrix on
/// the rest), corrected by a LocalSchwarzCorrection on the unknowns whose pattern changed since
/// the factor's (changedPatternUnknowns() with kLocalRings rings; at most half the unknowns,
/// beyond that G alone): the region a cut changed is solved exactly, so a step that splits nodes
/// needs no refactorization. Without a usable factor (first call, n_old > n_new, failed
/// factorization) factorize() factorizes synchronously.
///
/// Accuracy: same tolerance semantics as PcgSolver. If PCG fails (not converged within
/// min(pcgIterationCap, kFallbackIterations), breakdown) with a factor of other values than the
/// current matrix, solve() factorizes the current matrix synchronously and solves again from the
/// last iterate (reported iterations: both solves), so a result is as accurate as with the other
/// solvers; a non-SPD or non-finite matrix gives a failed report. While old factors keep failing
/// (the matrix changes too fast: large cuts, violent motion), the 1, 2, 4, ... (at most
/// refresh_interval) factorize() calls after each fallback factorize synchronously, so such
/// phases cost about as much as pcg_cholesky_reuse refactorizing at every call; a solve that
/// succeeds with an old factor ends the back-off. Which factor preconditions a solve depends on the
/// worker's timing, so results are reproducible to the tolerance, not bitwise.
///
/// Work vectors are allocated in analyzePattern() and factorize(); solve() allocates only when it
/// falls back to a synchronous factorization. Use from one thread. Not copyable or movable.
class BackgroundCholeskyPcgSolver final : public LinearSolver {
 public:
  /// A solve needing more PCG iterations than this requests a refresh at the next factorize()
  /// (with a current factor a solve takes 1-3 iterations, each about as costly as a matrix-vector
  /// product plus two triangular solves).
  static constexpr int kRefreshIterations = 4;
  /// Iteration budget of a solve preconditioned by a factor of other values (older or interim)
  /// before the synchronous fallback: about the cost of one analysis plus refactorization of a
  /// tissue matrix (docs/models.md, solver design notes). Beyond it, the matrix has changed too
  /// much for the old factor (e.g. a large cut) and iterating on costs more than refactorizing.
  static constexpr int kFallbackIterations = 50;
  /// Rings of pattern neighbours added around the changed unknowns of the interim preconditioner
  /// (more rings: fewer PCG iterations, dearer local solves; one ring costs least while cutting,
  /// docs/models.md).
  static constexpr int kLocalRings = 1;

  /// Starts the worker thread (idle until a refresh is due).
  /// @throws std::invalid_argument if settings are out of range (see validatePcgSettings).
  explicit BackgroundCholeskyPcgSolver(const PcgSettings& settings);
  /// Stops and joins the worker; waits for a running refresh to finish.
  ~BackgroundCholeskyPcgSolver() override;
  BackgroundCholeskyPcgSolver(const BackgroundCholeskyPcgSolver&) = delete;
  BackgroundCholeskyPcgSolver& operator=(const BackgroundCholeskyPcgSolver&) = delete;
  BackgroundCholeskyPcgSolver(BackgroundCholeskyPcgSolver&&) = delete;
  BackgroundCholeskyPcgSolver& operator=(BackgroundCholeskyPcgSolver&&) = delete;

  /// Returns "pcg_cholesky_background".
  std::string name() const override;
  /// Stores A's pattern and sizes the work vectors. A pattern equal to the stored one keeps
  /// everything; a new one keeps a factor of at most n rows as the start of the interim
  /// preconditioner (see the class comment). Cheap: CHOLMOD analyses in factorize().
  void analyzePattern(const Eigen::SparseMatrix<double>& A) override;
  /// Copies A's values, adopts a finished background factor, starts a due refresh and builds the
  /// preconditioner (synchronous factorization only without a usable factor). Returns false if the
  /// pattern differs from the analysed one, a value is not finite, a synchronous factorization
  /// failed or a block-Jacobi block is not positive definite.
  bool factorize(const Eigen::SparseMatrix<double>& A) override;
  /// PCG on A x = b from the initial guess x (size n), with the synchronous fallback described in
  /// the class comment. ok when the relative residual reaches relative_tolerance.
  LinearSolveReport solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;

  /// Number of factors computed by the worker and swapped in (for tests and benchmarks).
  int backgroundRefreshes() const { return background_refreshes_; }
  /// Number of factorizations done on the calling thread: first factorization, shrinking pattern,
  /// fallback of a failed solve and the back-off after it (for tests and benchmarks).
  int synchronousFactorizations() const { return synchronous_factorizations_; }
  /// Blocks until the worker has no refresh running (its result is adopted by the next
  /// factorize()). For tests and reproducible benchmarks.
  void waitForRefresh();

 private:
  /// A CHOLMOD solver with what its analysis and factor are of.
  struct FactorSlot {
    CholmodSolver cholmod{CholmodOrdering::Metis, CholmodPreconditioning::SinglePrecision};
    std::uint64_t pattern = 0;  ///< generation of the analysed pattern (0: none)
    std::uint64_t values = 0;   ///< factorize() call whose matrix was factorized (0: none)
    Eigen::Index rows = 0;      ///< size of the analysed pattern
    bool valid = false;         ///< holds a numeric factor
  };
  enum class WorkerState { Idle, Busy, Done };

  /// Worker thread: analyses (new pattern) and factorizes job_matrix_ into the spare slot.
  void runWorker();
  /// Analyses A into slot if its pattern generation differs, then factorizes A (sets slot.valid).
  static void factorizeInto(FactorSlot& slot, const Eigen::SparseMatrix<double>& A,
                            std::uint64_t pattern, std::uint64_t values);
  /// True if slot's factor can precondition matrix_ (alone or with the block-Jacobi tail).
  bool usable(const FactorSlot& slot) const;
  /// Swaps in a finished worker factor if it is usable and newer. Returns true if swapped.
  bool adoptRefresh();
  /// Hands matrix_ to the worker if a refresh is due and the worker is idle.
  void startRefreshIfDue();
  /// Factorizes matrix_ on this thread into the current slot. Returns false on failure.
  bool factorizeSynchronously();
  /// Builds the interim parts for the current factor and matrix_: the block-Jacobi tail for the
  /// unknowns the factor does not cover and, for a factor of an older pattern, the local
  /// correction (its unknowns recomputed when the pattern or the factor changed).
  void buildInterim();
  /// z = G r with the current factor and the block-Jacobi tail.
  bool applyFactorAndTail(const Eigen::VectorXd& r, Eigen::VectorXd& z);
  /// z = P^-1 r: G, with the local correction while the factor is of an older pattern.
  bool applyPreconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z);
  FactorSlot& current() { return slots_[static_cast<size_t>(current_)]; }

  PcgSettings settings_;
  int max_iterations_ = 0;              ///< pcgIterationCap of the analysed pattern
  Eigen::SparseMatrix<double> matrix_;  ///< analysed pattern, values of the last factorize()
  std::uint64_t pattern_ = 0;           ///< generation of matrix_'s pattern
  std::uint64_t values_ = 0;            ///< number of factorize() calls (matrix_ values stamp)
  /// Factors of earlier factorize() calls are unusable (a shrinking pattern renumbered unknowns).
  std::uint64_t first_usable_values_ = 0;
  CgWorkspace work_;
  BlockJacobi tail_;
  bool tail_ok_ = false;
  LocalSchwarzCorrection local_;
  bool local_ok_ = true;
  std::uint64_t local_pattern_ = 0;      ///< pattern_ that local_'s unknowns were computed for
  std::uint64_t local_factor_ = 0;       ///< values stamp of the factor they were computed against
  PreconditionerApply factor_and_tail_;  ///< applyFactorAndTail, the G of local_
  Eigen::VectorXd head_rhs_, head_solution_;  ///< interim preconditioner: factor part
  int calls_since_refresh_ = 0;
  bool refresh_requested_ = false;  ///< a solve needed more than kRefreshIterations
  int fallback_streak_ = 0;         ///< consecutive fallbacks (back-off exponent)
  int synchronous_calls_left_ = 0;  ///< factorize() calls left to factorize synchronously
  bool factorized_ = false;
  int background_refreshes_ = 0;
  int synchronous_factorizations_ = 0;

  // Hand-over. slots_[current_] belongs to the calling thread; the other slot and job_matrix_
  // belong to the worker while worker_state_ is Busy. current_ and worker_state_ are guarded by
  // mutex_.
  std::array<FactorSlot, 2> slots_;
  int current_ = 0;
  std::mutex mutex_;
  std::condition_variable changed_;  ///< worker_state_ or stop_ changed
  WorkerState worker_state_ = WorkerState::Idle;
  bool stop_ = false;
  Eigen::SparseMatrix<double> job_matrix_;
  std::uint64_t job_pattern_ = 0;
  std::uint64_t job_values_ = 0;
  std::thread worker_;  ///< last member: starts after everything it uses is constructed
};

}  // namespace surgical_sim::core
