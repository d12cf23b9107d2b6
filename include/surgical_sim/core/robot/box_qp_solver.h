#pragma once

#include <vector>

#include <Eigen/Core>

namespace surgical_sim::core {

/// Outcome of BoxQpSolver::solve.
enum class BoxQpStatus {
  Optimal,        ///< KKT conditions satisfied
  MaxIterations,  ///< iteration cap reached; x is feasible and no worse than the start
  NotConvex,      ///< a free-variable block of H is not positive definite
};

/// Result of BoxQpSolver::solve.
struct BoxQpReport {
  BoxQpStatus status = BoxQpStatus::Optimal;
  int iterations = 0;
};

/// Dense convex QP with box constraints, min 1/2 x^T H x + c^T x s.t. lo <= x <= hi, by a primal
/// active-set method: Newton step on the free variables (Cholesky of H_FF), ratio test to the
/// first blocking bound, release of the bound with the most negative multiplier. Exact in a
/// finite number of iterations for positive-definite H. Work storage sized in the constructor;
/// solve() allocates nothing.
class BoxQpSolver {
 public:
  /// @param size number of variables, >= 1.
  /// @throws std::invalid_argument "box_qp.size" if size < 1.
  explicit BoxQpSolver(int size);

  /// @param H symmetric positive-definite (size x size).
  /// @param c linear term (size).
  /// @param lo, hi bounds with lo <= hi (size); infinite bounds allowed.
  /// @param x in: warm start (clamped to the box); out: solution.
  /// @param max_iterations active-set iterations, >= 1.
  BoxQpReport solve(const Eigen::MatrixXd& H, const Eigen::VectorXd& c, const Eigen::VectorXd& lo,
                    const Eigen::VectorXd& hi, Eigen::VectorXd& x, int max_iterations);

 private:
  enum class Bound { Free, Lower, Upper };
  std::vector<Bound> state_;
  std::vector<int> free_;
  Eigen::MatrixXd chol_;
  Eigen::VectorXd gradient_, step_, rhs_;
};

}  // namespace surgical_sim::core
