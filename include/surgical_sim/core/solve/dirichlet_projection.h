#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

namespace surgical_sim::core {

/// Dirichlet conditions by projection, for a linear system A u = b of size N (N = 3n).
/// Stateless, allocation-free kernels. The constrained set is a mask of size N (1 = constrained).
///
/// Usage for prescribed values g on the constrained DOFs:
///   markDirichletDofs(dofs, mask);
///   applyDirichletRhs(A, mask, g, b);   // with the unprojected A
///   projectDirichletMatrix(mask, A);    // pattern kept, rows/cols zeroed, unit diagonal
/// then u_c = g_c exactly and u_f solves A_ff u_f = b_f - A_fc g_c.

/// Sets mask[i] = 1 for i in dofs, 0 elsewhere. mask keeps its size N (not resized).
/// Returns false (mask then marks only the valid DOFs) if a DOF is outside [0, N).
bool markDirichletDofs(const std::vector<int>& dofs, std::vector<std::uint8_t>& mask);

/// Zeroes every stored entry of A (square N x N, compressed, pattern kept) in a constrained row
/// or column and sets constrained diagonal entries to 1 (the diagonal must be in the pattern).
void projectDirichletMatrix(const std::vector<std::uint8_t>& mask, Eigen::SparseMatrix<double>& A);

/// Right-hand side treatment matching projectDirichletMatrix, called with the unprojected A:
/// b_f -= A_fc g_c for free rows, b_c = g_c. prescribed (g) and b have size N; only the
/// constrained entries of g are read.
void applyDirichletRhs(const Eigen::SparseMatrix<double>& A, const std::vector<std::uint8_t>& mask,
                       const Eigen::VectorXd& prescribed, Eigen::VectorXd& b);

/// v_c = 0 for every constrained DOF (homogeneous treatment of increments and residuals).
void zeroDirichletEntries(const std::vector<int>& dofs, Eigen::VectorXd& v);

}  // namespace surgical_sim::core
