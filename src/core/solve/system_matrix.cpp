#include "surgical_sim/core/solve/system_matrix.h"

#include <algorithm>

#include "surgical_sim/core/solve/dirichlet_projection.h"

namespace surgical_sim::core {

bool samePattern(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& B) {
  if (!A.isCompressed() || !B.isCompressed() || A.rows() != B.rows() || A.cols() != B.cols() ||
      A.nonZeros() != B.nonZeros()) {
    return false;
  }
  return std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.cols() + 1, B.outerIndexPtr()) &&
         std::equal(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros(), B.innerIndexPtr());
}

void SystemMatrix::setPattern(const Eigen::SparseMatrix<double>& stiffness_pattern) {
  Eigen::SparseMatrix<double> compressed;
  const Eigen::SparseMatrix<double>* K = &stiffness_pattern;
  if (!K->isCompressed()) {
    compressed = stiffness_pattern;
    compressed.makeCompressed();
    K = &compressed;
  }
  const auto n = static_cast<int>(K->rows());
  const int* k_outer = K->outerIndexPtr();
  const int* k_inner = K->innerIndexPtr();
  const double* k_value = K->valuePtr();
  stiffness_nonzeros_ = K->nonZeros();
  stiffness_to_system_.resize(static_cast<size_t>(stiffness_nonzeros_));
  diagonal_entry_.resize(static_cast<size_t>(n));
  // A = K + I column by column: K's entries with the diagonal merged in (added to K's diagonal
  // entry, or inserted at its sorted place where K has none).
  matrix_.resize(n, n);
  matrix_.resizeNonZeros(stiffness_nonzeros_ + n);
  int* a_outer = matrix_.outerIndexPtr();
  int* a_inner = matrix_.innerIndexPtr();
  double* a_value = matrix_.valuePtr();
  int a = 0;
  const auto insertDiagonal = [&](int j) {
    a_inner[a] = j;
    a_value[a] = 1.0;
    diagonal_entry_[static_cast<size_t>(j)] = a++;
  };
  for (int j = 0; j < n; ++j) {
    a_outer[j] = a;
    bool diagonal = false;
    for (int k = k_outer[j]; k < k_outer[j + 1]; ++k) {
      if (!diagonal && k_inner[k] > j) {
        insertDiagonal(j);
        diagonal = true;
      }
      a_inner[a] = k_inner[k];
      a_value[a] = k_value[k];
      stiffness_to_system_[static_cast<size_t>(k)] = a;
      if (k_inner[k] == j) {
        a_value[a] += 1.0;
        diagonal_entry_[static_cast<size_t>(j)] = a;
        diagonal = true;
      }
      ++a;
    }
    if (!diagonal) insertDiagonal(j);
  }
  a_outer[n] = a;
  matrix_.data().resize(a);
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
