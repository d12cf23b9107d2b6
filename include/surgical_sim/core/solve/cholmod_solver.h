#pragma once

#include <cholmod.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "surgical_sim/core/solve/linear_solver.h"
#include "surgical_sim/core/solve/single_precision_cholesky.h"

namespace surgical_sim::core {

/// Fill-reducing ordering of a CholmodSolver.
enum class CholmodOrdering {
  /// METIS nested dissection: less fill and fewer factorization flops than AMD on 3D tissue
  /// meshes, for a longer analysis. For 3D tissue meshes.
  Metis,
  /// AMD only: the cheapest analysis, for small or slab-like matrices analysed often (the local
  /// correction of a cut; CHOLMOD's own default would also try METIS when AMD fills much).
  Amd,
};

/// What CholmodSolver::precondition() solves with.
enum class CholmodPreconditioning {
  Double,  ///< the CHOLMOD factor (solveWithFactor)
  /// A SinglePrecisionCholesky copy made by every factorize() (an extra pass over the factor, so
  /// best on a thread that factorizes in the background); the double factor if it cannot be
  /// copied.
  SinglePrecision,
};

/// Direct sparse solver: CHOLMOD supernodal LL^T of a symmetric positive-definite matrix.
///
/// The fill-reducing ordering (see CholmodOrdering) and symbolic factor are computed once per
/// pattern in analyzePattern(); factorize() recomputes only the numeric factor. Only the lower
/// triangle of the (full, symmetric) input matrix is read. solve() reuses CHOLMOD workspaces
/// (cholmod_solve2), so after the first call it allocates nothing.
/// Not copyable or movable (owns CHOLMOD state).
class CholmodSolver final : public LinearSolver {
 public:
  explicit CholmodSolver(CholmodOrdering ordering = CholmodOrdering::Metis,
                         CholmodPreconditioning preconditioning = CholmodPreconditioning::Double);
  ~CholmodSolver() override;
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;
  CholmodSolver(CholmodSolver&&) = delete;
  CholmodSolver& operator=(CholmodSolver&&) = delete;

  /// Returns "cholmod".
  std::string name() const override;
  /// Symbolic analysis (ordering + supernodal structure) of A's pattern, A square n x n.
  void analyzePattern(const Eigen::SparseMatrix<double>& A) override;
  /// analyzePattern() of a changed pattern of the same size that keeps the fill-reducing ordering
  /// of the current analysis (a cut adds or removes a few couplings; the ordering, most of an
  /// analysis's cost, stays good). Orders afresh without a current analysis of the same size, or
  /// when the kept ordering's factor entries per matrix entry exceed kMaxKeptOrderingFill times
  /// those of the last fresh ordering.
  void analyzeChangedPattern(const Eigen::SparseMatrix<double>& A) override;
  /// Factor fill growth (entries of L per entry of A, relative to the last fresh ordering) up to
  /// which analyzeChangedPattern() keeps the ordering. On the progressive EFG scalpel cuts a
  /// kept ordering fills 1.0-1.4 times as much; 1.1 gave the fastest steps (1.2: more fill costs
  /// more than the orderings it saves).
  static constexpr double kMaxKeptOrderingFill = 1.1;
  /// Fresh fill-reducing orderings since construction (for tests and benchmarks).
  int orderings() const { return orderings_; }
  /// Numeric LL^T of A (same pattern as analysed). Returns false if A is not positive definite,
  /// its pattern differs from the analysed one, or CHOLMOD reports an error.
  bool factorize(const Eigen::SparseMatrix<double>& A) override;
  /// Solves A x = b with the current factor (x on entry ignored), b and x of size n.
  /// iterations = 1; relative_residual = |b - A x| / |b| (computed with the factorized matrix).
  LinearSolveReport solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
  /// x = A^-1 b with the current factor, without solve()'s residual (one matrix-vector product
  /// less: for use as a preconditioner). Returns false if there is no factor, sizes differ or
  /// CHOLMOD fails; x may be non-finite if the factor is nearly singular.
  bool solveWithFactor(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// x ~= A^-1 b for preconditioning: with the single-precision copy if the solver was built for
  /// it and the copy exists, else as solveWithFactor() (same failures).
  bool precondition(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// The analysed pattern with the values of the last factorize() call.
  const Eigen::SparseMatrix<double>& analysedMatrix() const { return matrix_; }
  /// Entries of the factor L (0 before analyzePattern()).
  double factorNonzeros() const { return factor_ == nullptr ? 0.0 : common_.lnz; }
  /// Flops of one numeric factorization, CHOLMOD's count (0 before analyzePattern()).
  double factorFlops() const { return factor_ == nullptr ? 0.0 : common_.fl; }
  /// The numeric factor of the last successful factorize() (nullptr without one).
  const cholmod_factor* numericFactor() const { return factorized_ ? factor_ : nullptr; }

 private:
  void releaseFactor();
  /// Releases the factor, copies A and analyses it: with a fresh ordering (counted, its fill
  /// stored) if ordering is null, else with the given one (permuted as CHOLMOD_GIVEN).
  void analyzeWithOrdering(const Eigen::SparseMatrix<double>& A, std::vector<int>* ordering);
  /// Entries of L per entry of the analysed matrix (0 without an analysis).
  double fill() const;
  cholmod_sparse viewOf(const Eigen::SparseMatrix<double>& A) const;

  cholmod_common common_;
  cholmod_factor* factor_ = nullptr;
  cholmod_dense* solution_ = nullptr;     ///< X of cholmod_solve2, reused
  cholmod_dense* workspace_y_ = nullptr;  ///< Y workspace of cholmod_solve2, reused
  cholmod_dense* workspace_e_ = nullptr;  ///< E workspace of cholmod_solve2, reused
  Eigen::SparseMatrix<double> matrix_;    ///< copy of the last factorized matrix (for residuals)
  Eigen::VectorXd residual_;              ///< n, work vector
  CholmodPreconditioning preconditioning_;
  SinglePrecisionCholesky single_;  ///< copy of the factor (SinglePrecision only)
  bool factorized_ = false;
  int orderings_ = 0;
  double ordered_fill_ = 0.0;  ///< entries of L per entry of A at the last fresh ordering
};

}  // namespace surgical_sim::core
