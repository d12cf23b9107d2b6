#include "surgical_sim/core/solve/local_schwarz_correction.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace surgical_sim::core {
namespace {

/// True if column j of A has the same nonzero rows as column j of previous.
bool sameColumn(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& previous,
                Eigen::Index j) {
  if (j >= previous.cols()) return false;
  const int* a = A.innerIndexPtr() + A.outerIndexPtr()[j];
  const int* a_end = A.innerIndexPtr() + A.outerIndexPtr()[j + 1];
  const int* p = previous.innerIndexPtr() + previous.outerIndexPtr()[j];
  const int* p_end = previous.innerIndexPtr() + previous.outerIndexPtr()[j + 1];
  return a_end - a == p_end - p && std::equal(a, a_end, p);
}

}  // namespace

std::vector<int> changedPatternUnknowns(const Eigen::SparseMatrix<double>& A,
                                        const Eigen::SparseMatrix<double>& previous, int rings) {
  const Eigen::Index n = A.cols();
  std::vector<std::uint8_t> marked(static_cast<size_t>((n + 2) / 3), 0);
  std::vector<int> frontier, layer;
  const auto mark = [&](Eigen::Index node) {
    if (marked[static_cast<size_t>(node)] != 0) return;
    marked[static_cast<size_t>(node)] = 1;
    frontier.push_back(static_cast<int>(node));
  };
  for (Eigen::Index j = 0; j < n; ++j) {
    if (!sameColumn(A, previous, j)) mark(j / 3);
  }
  for (int ring = 0; ring < rings; ++ring) {
    layer.swap(frontier);
    frontier.clear();
    for (const int node : layer) {
      for (Eigen::Index j = 3 * node; j < std::min<Eigen::Index>(3 * node + 3, n); ++j) {
        for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) mark(it.row() / 3);
      }
    }
  }
  std::vector<int> unknowns;
  for (size_t node = 0; node < marked.size(); ++node) {
    if (marked[node] == 0) continue;
    for (Eigen::Index j = 3 * static_cast<Eigen::Index>(node);
         j < std::min<Eigen::Index>(3 * static_cast<Eigen::Index>(node) + 3, n); ++j) {
      unknowns.push_back(static_cast<int>(j));
    }
  }
  return unknowns;
}

void LocalSchwarzCorrection::setUnknowns(const Eigen::SparseMatrix<double>& A,
                                         std::vector<int> unknowns) {
  unknowns_ = std::move(unknowns);
  const Eigen::Index m = static_cast<Eigen::Index>(unknowns_.size());
  std::vector<int> position(static_cast<size_t>(A.rows()), -1);
  for (Eigen::Index k = 0; k < m; ++k) position[static_cast<size_t>(unknowns_[k])] = k;
  // A_LL column by column; its rows come out sorted because L is.
  std::vector<int> outer(static_cast<size_t>(m) + 1, 0), inner;
  gather_.clear();
  for (Eigen::Index k = 0; k < m; ++k) {
    const int j = unknowns_[static_cast<size_t>(k)];
    for (int p = A.outerIndexPtr()[j]; p < A.outerIndexPtr()[j + 1]; ++p) {
      const int row = position[static_cast<size_t>(A.innerIndexPtr()[p])];
      if (row < 0) continue;
      inner.push_back(row);
      gather_.push_back(p);
    }
    outer[static_cast<size_t>(k) + 1] = static_cast<int>(inner.size());
  }
  const std::vector<double> zeros(inner.size(), 0.0);
  local_ = Eigen::Map<const Eigen::SparseMatrix<double>>(
      m, m, static_cast<Eigen::Index>(inner.size()), outer.data(), inner.data(), zeros.data());
  if (m > 0) factor_.analyzePattern(local_);
  local_rhs_.setZero(m);
  local_solution_.setZero(m);
  residual_.setZero(A.rows());
  correction_.setZero(A.rows());
}

bool LocalSchwarzCorrection::factorize(const Eigen::SparseMatrix<double>& A) {
  double* values = local_.valuePtr();
  for (size_t k = 0; k < gather_.size(); ++k) values[k] = A.valuePtr()[gather_[k]];
  return factor_.factorize(local_);
}

bool LocalSchwarzCorrection::addLocalSolve(Eigen::VectorXd& z) {
  if (!factor_.solveWithFactor(local_rhs_, local_solution_)) return false;
  for (size_t k = 0; k < unknowns_.size(); ++k) {
    z[unknowns_[k]] += local_solution_[static_cast<Eigen::Index>(k)];
  }
  return true;
}

bool LocalSchwarzCorrection::apply(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& r,
                                   Eigen::VectorXd& z, const PreconditionerApply& global) {
  z.setZero();
  for (size_t k = 0; k < unknowns_.size(); ++k) {
    local_rhs_[static_cast<Eigen::Index>(k)] = r[unknowns_[k]];
  }
  if (!addLocalSolve(z)) return false;
  // residual = r - A z, z nonzero on L only: the columns of L.
  residual_ = r;
  for (const int j : unknowns_) {
    const double zj = z[j];
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      residual_[it.row()] -= it.value() * zj;
    }
  }
  if (!global(residual_, correction_)) return false;
  z += correction_;
  // (r - A z)_L by the columns of L (A symmetric).
  for (size_t k = 0; k < unknowns_.size(); ++k) {
    const int i = unknowns_[k];
    double s = r[i];
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, i); it; ++it) {
      s -= it.value() * z[it.row()];
    }
    local_rhs_[static_cast<Eigen::Index>(k)] = s;
  }
  return addLocalSolve(z);
}

}  // namespace surgical_sim::core
