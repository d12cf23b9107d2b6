#include "surgical_sim/core/solve/system_matrix.h"

#include <algorithm>

#include "surgical_sim/core/solve/dirichlet_projection.h"

namespace surgical_sim::core {
namespace {

/// True if every column of the compressed square A has its diagonal entry.
bool hasFullDiagonal(const Eigen::SparseMatrix<double>& A) {
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    const int* begin = A.innerIndexPtr() + A.outerIndexPtr()[j];
    const int* end = A.innerIndexPtr() + A.outerIndexPtr()[j + 1];
    if (!std::binary_search(begin, end, static_cast<int>(j))) return false;
  }
  return true;
}

}  // namespace

void SystemMatrix::setPattern(const Eigen::SparseMatrix<double>& stiffness_pattern) {
  const Eigen::Index n = stiffness_pattern.rows();
  Eigen::SparseMatrix<double> pattern = stiffness_pattern;
  pattern.makeCompressed();
  if (hasFullDiagonal(pattern)) {
    matrix_ = pattern;  // the usual node-block pattern: no sparse sum needed
  } else {
    Eigen::SparseMatrix<double> identity(n, n);
    identity.setIdentity();
    matrix_ = pattern + identity;
    matrix_.makeCompressed();
  }
  stiffness_nonzeros_ = pattern.nonZeros();
  stiffness_to_system_.assign(static_cast<size_t>(pattern.nonZeros()), 0);
  diagonal_entry_.assign(static_cast<size_t>(n), 0);
  const int* k_outer = pattern.outerIndexPtr();
  const int* k_inner = pattern.innerIndexPtr();
  const int* a_outer = matrix_.outerIndexPtr();
  const int* a_inner = matrix_.innerIndexPtr();
  for (Eigen::Index j = 0; j < n; ++j) {
    int a = a_outer[j];
    for (int k = k_outer[j]; k < k_outer[j + 1]; ++k) {
      while (a_inner[a] != k_inner[k]) ++a;  // A's column j is a sorted superset of K's
      stiffness_to_system_[static_cast<size_t>(k)] = a;
    }
    for (int e = a_outer[j]; e < a_outer[j + 1]; ++e) {
      if (a_inner[e] == j) diagonal_entry_[static_cast<size_t>(j)] = e;
    }
  }
}

bool SystemMatrix::matchesPattern(const Eigen::SparseMatrix<double>& stiffness_pattern) const {
  return stiffness_pattern.rows() == matrix_.rows() &&
         stiffness_pattern.nonZeros() == stiffness_nonzeros_;
}

void SystemMatrix::assemble(const Eigen::VectorXd& mass, double mass_coefficient,
                            const Eigen::SparseMatrix<double>& K, double stiffness_coefficient) {
  double* a = matrix_.valuePtr();
  std::fill(a, a + matrix_.nonZeros(), 0.0);
  for (Eigen::Index i = 0; i < mass.size(); ++i) {
    a[diagonal_entry_[static_cast<size_t>(i)]] = mass_coefficient * mass[i];
  }
  addStiffness(K, stiffness_coefficient);
}

void SystemMatrix::addStiffness(const Eigen::SparseMatrix<double>& K, double coefficient) {
  double* a = matrix_.valuePtr();
  const double* k = K.valuePtr();
  for (size_t e = 0; e < stiffness_to_system_.size(); ++e) {
    a[stiffness_to_system_[e]] += coefficient * k[e];
  }
}

void SystemMatrix::projectDirichlet(const std::vector<std::uint8_t>& mask) {
  projectDirichletMatrix(mask, matrix_);
}

}  // namespace surgical_sim::core
