#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace surgical_sim::core {

/// || |A| |x| ||_2 (entry-wise absolute values): the scale of the round-off in evaluating A x
/// (or a force linear in x) in floating point, used by the Newton solvers to recognise residuals
/// that cannot be reduced further. A: N x N compressed; x, work: size N (work is overwritten).
/// Allocation-free.
double absoluteProductNorm(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& x,
                           Eigen::VectorXd& work);

}  // namespace surgical_sim::core
