#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>

#include "surgical_sim/core/solve/linear_solver.h"

namespace surgical_sim::core {

/// Work vectors of preconditionedConjugateGradient. Sized once per pattern (resize), so that
/// solves allocate nothing.
struct CgWorkspace {
  Eigen::VectorXd residual, direction, product, preconditioned;
  /// Sizes every vector to n (zero-filled).
  void resize(Eigen::Index n);
};

/// Copies A's values into the analysed matrix `into` if A is compressed with its dimensions and
/// number of nonzeros (the pattern itself is the caller's contract); returns false otherwise.
bool copyValuesOfSamePattern(const Eigen::SparseMatrix<double>& A,
                             Eigen::SparseMatrix<double>& into);

/// z = P^-1 r of a symmetric positive-definite preconditioner P (z has r's size on entry).
/// Returns false if the application failed. A lambda capturing one pointer is stored without
/// allocation.
using PreconditionerApply = std::function<bool(const Eigen::VectorXd& r, Eigen::VectorXd& z)>;

/// Preconditioned conjugate gradient on A x = b (A symmetric positive definite, n x n) from the
/// initial guess x (size n; replaced by 0 if not finite). ok when the relative residual
/// |b - A x| / |b| reaches relative_tolerance within max_iterations (b = 0 gives x = 0, ok).
/// Fails (ok = false) on size mismatch, non-finite b, breakdown (p^T A p <= 0, NaN) or a failed
/// preconditioner application; iterations and relative_residual report the last iterate, capped
/// is set when max_iterations ran out without breakdown.
LinearSolveReport preconditionedConjugateGradient(const Eigen::SparseMatrix<double>& A,
                                                  const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                                  int max_iterations, double relative_tolerance,
                                                  const PreconditionerApply& precondition,
                                                  CgWorkspace& work);

}  // namespace surgical_sim::core
