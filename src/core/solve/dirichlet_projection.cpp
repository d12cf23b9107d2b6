#include "surgical_sim/core/solve/dirichlet_projection.h"

#include <algorithm>

namespace surgical_sim::core {

bool markDirichletDofs(const std::vector<int>& dofs, std::vector<std::uint8_t>& mask) {
  std::fill(mask.begin(), mask.end(), std::uint8_t{0});
  bool valid = true;
  const int size = static_cast<int>(mask.size());
  for (const int dof : dofs) {
    if (dof < 0 || dof >= size) {
      valid = false;
      continue;
    }
    mask[static_cast<size_t>(dof)] = 1;
  }
  return valid;
}

void projectDirichletMatrix(const std::vector<std::uint8_t>& mask, Eigen::SparseMatrix<double>& A) {
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    const bool column_constrained = mask[static_cast<size_t>(j)] != 0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      if (column_constrained || mask[static_cast<size_t>(it.row())] != 0) {
        it.valueRef() = it.row() == j ? 1.0 : 0.0;
      }
    }
  }
}

void applyDirichletRhs(const Eigen::SparseMatrix<double>& A, const std::vector<std::uint8_t>& mask,
                       const Eigen::VectorXd& prescribed, Eigen::VectorXd& b) {
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    if (mask[static_cast<size_t>(j)] == 0) continue;
    const double g = prescribed[j];
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      if (mask[static_cast<size_t>(it.row())] == 0) b[it.row()] -= it.value() * g;
    }
  }
  for (Eigen::Index i = 0; i < b.size(); ++i) {
    if (mask[static_cast<size_t>(i)] != 0) b[i] = prescribed[i];
  }
}

void zeroDirichletEntries(const std::vector<int>& dofs, Eigen::VectorXd& v) {
  for (const int dof : dofs) v[dof] = 0.0;
}

}  // namespace surgical_sim::core
