#pragma once

#include <Eigen/Core>
#include <vector>

namespace surgical_sim::core {

class CholmodSolver;

/// Single-precision copy of a CholmodSolver's supernodal factor L (P A P^T = L L^T), for use as a
/// preconditioner: its triangular solves stream half the memory of the double factor, and the
/// copy stays in the last-level cache more often while another thread factorizes. Its relative
/// error (about float's epsilon times the condition growth) is what PCG corrects.
///
/// The copy holds everything it needs (ordering, supernode structure, values), so it stays valid
/// while the solver analyses or factorizes other matrices. Work vectors are reused: after the
/// first solve() of a size, solve() allocates nothing.
class SinglePrecisionCholesky {
 public:
  /// Copies the solver's numeric factor. Returns false, and holds no factor, if the solver has
  /// none, its factor is not supernodal LL^T, a value is not finite in single precision (beyond
  /// ~3e38) or a pivot is below float's normal range (~1e-38): use the double factor then.
  bool assign(const CholmodSolver& solver);
  /// True if assign() succeeded.
  bool valid() const { return !perm_.empty(); }
  /// Size n of the factorized matrix (0 without a factor).
  Eigen::Index rows() const { return static_cast<Eigen::Index>(perm_.size()); }
  /// z = A^-1 r with the copied factor, rounded to single precision (r and z of size rows(); z
  /// is resized). Solves for r / max|r_i| and scales back, so any finite r keeps its relative
  /// accuracy; r = 0 gives z = 0, a non-finite r a non-finite z. Requires valid().
  void solve(const Eigen::VectorXd& r, Eigen::VectorXd& z);

 private:
  std::vector<int> perm_;          ///< pivot k is unknown perm_[k]
  std::vector<int> first_column_;  ///< supernode s: columns [first_column_[s], [s + 1])
  std::vector<int> row_start_;     ///< supernode s: rows_[row_start_[s], [s + 1])
  std::vector<int> value_start_;   ///< supernode s: column-major block at values_[value_start_[s]]
  std::vector<int> rows_;          ///< row indices of each supernode, its own columns first
  std::vector<float> values_;      ///< L, supernode blocks of rows x columns
  Eigen::VectorXf permuted_, below_;  ///< work vectors: P r (then the solution), below-block rows
};

}  // namespace surgical_sim::core
