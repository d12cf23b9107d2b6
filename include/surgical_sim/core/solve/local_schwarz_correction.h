#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "surgical_sim/core/solve/cholmod_solver.h"
#include "surgical_sim/core/solve/conjugate_gradient.h"

namespace surgical_sim::core {

/// Unknowns around the pattern change from `previous` to A (both square, compressed; unknowns
/// are node coordinates, 3 per node): the nodes having a column whose nonzero rows differ from
/// previous's (columns past previous.cols() are new), grown by `rings` layers of pattern
/// neighbours in A, as the sorted list of their unknowns in [0, A.rows()). After a cut these are
/// the split nodes, the corners of the changed elements and the appended nodes; empty if the
/// patterns are equal.
std::vector<int> changedPatternUnknowns(const Eigen::SparseMatrix<double>& A,
                                        const Eigen::SparseMatrix<double>& previous, int rings);

/// Symmetric multiplicative Schwarz correction of a global preconditioner G on a subset L of the
/// unknowns, with the exact solve of A_LL (CHOLMOD):
///   z = A_LL^-1 r_L;  z += G (r - A z);  z += A_LL^-1 (r - A z)_L,
/// a symmetric positive-definite preconditioner for SPD A and G. When G is the factor of an
/// older matrix that differs from A only near L (a stale factor after a cut, where L is the
/// changed region plus a ring), the local solves remove the error G makes there, so PCG needs a
/// few iterations where G alone needs hundreds.
///
/// setUnknowns() fixes L and A's pattern and analyses A_LL's pattern (CHOLMOD); factorize() then
/// copies A_LL's values and factorizes them. apply() allocates
/// nothing; its products with A touch only the columns of L. Not copyable (owns CHOLMOD state).
class LocalSchwarzCorrection {
 public:
  /// Sets L (sorted, unique, in [0, A.rows())), records where A_LL's entries are in A's
  /// compressed values and analyses A_LL's pattern. Empty L disables the correction (active()
  /// false).
  void setUnknowns(const Eigen::SparseMatrix<double>& A, std::vector<int> unknowns);
  /// Copies A_LL from A (the pattern given to setUnknowns()) and factorizes it. Returns false if
  /// A_LL is not positive definite (then A is not either).
  bool factorize(const Eigen::SparseMatrix<double>& A);
  /// z = the corrected preconditioner applied to r (A as in factorize(); r, z of size n).
  /// Returns false if a solve or the global preconditioner failed.
  bool apply(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& r, Eigen::VectorXd& z,
             const PreconditionerApply& global);
  /// True once setUnknowns() got a non-empty L.
  bool active() const { return !unknowns_.empty(); }
  /// The unknowns L.
  const std::vector<int>& unknowns() const { return unknowns_; }

 private:
  /// Solves A_LL y = local_rhs_ and adds y to z's entries of L.
  bool addLocalSolve(Eigen::VectorXd& z);

  std::vector<int> unknowns_;
  Eigen::SparseMatrix<double> local_;  ///< A_LL
  std::vector<int> gather_;            ///< per entry of local_: its entry in A's values
  CholmodSolver factor_{CholmodOrdering::Amd};
  Eigen::VectorXd local_rhs_, local_solution_, residual_, correction_;
};

}  // namespace surgical_sim::core
