#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "surgical_sim/core/common/thread_pool.h"

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
///
/// Two threads: assign() splits the supernodal elimination tree into a top (the supernodes on the
/// heaviest path from the root down to where the rest splits evenly) and two bins of disjoint
/// subtrees of about equal work. The triangular solves run the bins concurrently (forward: each
/// bin's updates of top rows go to its own buffer, added bin 0 then bin 1; backward: the top
/// first, then the bins), the top alone. The arithmetic order is fixed by the split, not by the
/// threads, so z is bit-identical for any thread count.
class SinglePrecisionCholesky {
 public:
  /// @param threads threads of the triangular solves (1: the calling thread alone; at most 2 are
  ///        used), in [1, kMaxThreads]
  explicit SinglePrecisionCholesky(int threads = defaultThreadCount());

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
  using Block = Eigen::Map<const Eigen::MatrixXf, 0, Eigen::OuterStride<>>;
  /// Supernode s: its columns [first, first + columns) in the block's top rows, then the rows
  /// below (indices `rows`).
  struct Supernode {
    int first, columns, below;
    const int* rows;
    Block block;
  };
  Supernode supernode(int s) const;

  int threads_ = 1;
  std::vector<int> perm_;          ///< pivot k is unknown perm_[k]
  std::vector<int> first_column_;  ///< supernode s: columns [first_column_[s], [s + 1])
  std::vector<int> row_start_;     ///< supernode s: rows_[row_start_[s], [s + 1])
  std::vector<int> value_start_;   ///< supernode s: column-major block at values_[value_start_[s]]
  std::vector<int> rows_;          ///< row indices of each supernode, its own columns first
  std::vector<float> values_;      ///< L, supernode blocks of rows x columns
  /// Supernodes of bin 0, bin 1 and the top (index 2), each ascending.
  std::vector<int> order_[3];
  std::vector<int> top_rows_;         ///< pivots in top supernodes
  std::vector<char> in_top_;          ///< per pivot: its supernode is in the top
  Eigen::VectorXf permuted_;          ///< work vector: P r (then the solution)
  Eigen::VectorXf below_[3];          ///< per bin (and top): below-block rows
  Eigen::VectorXf top_update_[2];     ///< per bin: its forward updates of top rows (size n)
  std::shared_ptr<ThreadPool> pool_;  ///< null for one thread; made by the first assign()

  /// Splits the supernodes into the bins and the top (class comment).
  void splitTree();
  /// Forward substitution over the supernodes of bin `bin` (0, 1: top rows to top_update_; 2:
  /// the top).
  void forward(int bin);
  /// Backward substitution with L^T over the supernodes of bin `bin`, descending.
  void backward(int bin);
  /// Runs task(0) and task(1), concurrently with a pool.
  template <typename Task>
  void bothBins(Task&& task) {
    if (pool_) {
      pool_->run(2, [&task](int bin) { task(bin); });
    } else {
      task(0);
      task(1);
    }
  }
};

}  // namespace surgical_sim::core
