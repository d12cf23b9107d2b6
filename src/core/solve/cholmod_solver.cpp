#include "surgical_sim/core/solve/cholmod_solver.h"

#include "surgical_sim/core/solve/single_thread_blas.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace surgical_sim::core {

CholmodSolver::CholmodSolver(CholmodOrdering ordering, CholmodPreconditioning preconditioning)
    : preconditioning_(preconditioning) {
  useSingleThreadBlas();
  cholmod_start(&common_);
  common_.print = 0;  // the library reports through return values, never prints
  common_.supernodal = CHOLMOD_SUPERNODAL;
  common_.final_ll = 1;
  common_.nmethods = 1;
  common_.method[0].ordering = ordering == CholmodOrdering::Metis ? CHOLMOD_METIS : CHOLMOD_AMD;
}

CholmodSolver::~CholmodSolver() {
  releaseFactor();
  cholmod_finish(&common_);
}

std::string CholmodSolver::name() const { return "cholmod"; }

void CholmodSolver::releaseFactor() {
  if (factor_ != nullptr) cholmod_free_factor(&factor_, &common_);
  if (solution_ != nullptr) cholmod_free_dense(&solution_, &common_);
  if (workspace_y_ != nullptr) cholmod_free_dense(&workspace_y_, &common_);
  if (workspace_e_ != nullptr) cholmod_free_dense(&workspace_e_, &common_);
  factorized_ = false;
}

cholmod_sparse CholmodSolver::viewOf(const Eigen::SparseMatrix<double>& A) const {
  cholmod_sparse view{};
  view.nrow = static_cast<size_t>(A.rows());
  view.ncol = static_cast<size_t>(A.cols());
  view.nzmax = static_cast<size_t>(A.nonZeros());
  view.p = const_cast<int*>(A.outerIndexPtr());
  view.i = const_cast<int*>(A.innerIndexPtr());
  view.x = const_cast<double*>(A.valuePtr());
  view.nz = nullptr;
  view.z = nullptr;
  view.stype = -1;  // symmetric, lower triangle used
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = 1;
  return view;
}

void CholmodSolver::analyzePattern(const Eigen::SparseMatrix<double>& A) {
  releaseFactor();
  matrix_ = A;
  matrix_.makeCompressed();
  residual_.resize(A.rows());
  cholmod_sparse view = viewOf(matrix_);
  std::vector<int> ordering;
  if (common_.method[0].ordering == CHOLMOD_METIS) ordering = nodeBlockOrdering(matrix_);
  if (ordering.empty()) {
    factor_ = cholmod_analyze(&view, &common_);
    return;
  }
  common_.method[0].ordering = CHOLMOD_GIVEN;
  factor_ = cholmod_analyze_p(&view, ordering.data(), nullptr, 0, &common_);
  common_.method[0].ordering = CHOLMOD_METIS;
}

std::vector<int> CholmodSolver::nodeBlockOrdering(const Eigen::SparseMatrix<double>& A) {
  const Eigen::Index n = A.rows();
  if (n % 3 != 0 || n == 0 || A.cols() != n) return {};
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  // Node pattern from the first column of each node, if every node's three columns have the same
  // rows and those come in whole node triples.
  const Eigen::Index nodes = n / 3;
  std::vector<int> node_outer(static_cast<size_t>(nodes) + 1, 0), node_inner;
  node_inner.reserve(static_cast<size_t>(A.nonZeros() / 9));
  for (Eigen::Index k = 0; k < nodes; ++k) {
    const int begin = outer[3 * k], length = outer[3 * k + 1] - begin;
    if (length % 3 != 0) return {};
    for (int c = 1; c < 3; ++c) {
      const int other = outer[3 * k + c];
      if (outer[3 * k + c + 1] - other != length ||
          !std::equal(inner + begin, inner + begin + length, inner + other)) {
        return {};
      }
    }
    for (int p = begin; p < begin + length; p += 3) {
      if (inner[p] % 3 != 0 || inner[p + 1] != inner[p] + 1 || inner[p + 2] != inner[p] + 2)
        return {};
      node_inner.push_back(inner[p] / 3);
    }
    node_outer[static_cast<size_t>(k) + 1] = static_cast<int>(node_inner.size());
  }
  cholmod_sparse graph{};
  graph.nrow = graph.ncol = static_cast<size_t>(nodes);
  graph.nzmax = node_inner.size();
  graph.p = node_outer.data();
  graph.i = node_inner.data();
  graph.stype = -1;
  graph.itype = CHOLMOD_INT;
  graph.xtype = CHOLMOD_PATTERN;
  graph.dtype = CHOLMOD_DOUBLE;
  graph.sorted = 1;
  graph.packed = 1;
  std::vector<int> node_order(static_cast<size_t>(nodes));
  if (cholmod_metis(&graph, nullptr, 0, 1, node_order.data(), &common_) == 0) return {};
  std::vector<int> ordering(static_cast<size_t>(n));
  for (Eigen::Index k = 0; k < nodes; ++k) {
    for (int c = 0; c < 3; ++c) ordering[static_cast<size_t>(3 * k + c)] = 3 * node_order[k] + c;
  }
  return ordering;
}

bool CholmodSolver::factorize(const Eigen::SparseMatrix<double>& A) {
  factorized_ = false;
  if (factor_ == nullptr || !A.isCompressed() || A.rows() != matrix_.rows() ||
      A.cols() != matrix_.cols() || A.nonZeros() != matrix_.nonZeros()) {
    return false;
  }
  std::copy(A.valuePtr(), A.valuePtr() + A.nonZeros(), matrix_.valuePtr());
  cholmod_sparse view = viewOf(matrix_);
  const int ok = cholmod_factorize(&view, factor_, &common_);
  if (ok == 0 || common_.status != CHOLMOD_OK || factor_->minor < factor_->n) return false;
  factorized_ = true;
  if (preconditioning_ == CholmodPreconditioning::SinglePrecision) single_.assign(*this);
  return true;
}

bool CholmodSolver::solveWithFactor(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!factorized_ || b.size() != matrix_.rows() || x.size() != b.size()) return false;
  cholmod_dense rhs{};
  rhs.nrow = static_cast<size_t>(b.size());
  rhs.ncol = 1;
  rhs.nzmax = rhs.nrow;
  rhs.d = rhs.nrow;
  rhs.x = const_cast<double*>(b.data());
  rhs.z = nullptr;
  rhs.xtype = CHOLMOD_REAL;
  rhs.dtype = CHOLMOD_DOUBLE;
  const int ok = cholmod_solve2(CHOLMOD_A, factor_, &rhs, nullptr, &solution_, nullptr,
                                &workspace_y_, &workspace_e_, &common_);
  if (ok == 0 || solution_ == nullptr) return false;
  x = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(solution_->x), b.size());
  return true;
}

bool CholmodSolver::precondition(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!factorized_ || !single_.valid() || b.size() != single_.rows()) return solveWithFactor(b, x);
  single_.solve(b, x);
  return true;
}

LinearSolveReport CholmodSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  LinearSolveReport report;
  if (!solveWithFactor(b, x)) return report;
  report.iterations = 1;
  if (!x.allFinite()) return report;
  residual_ = b;
  residual_.noalias() -= matrix_ * x;
  const double b_norm = b.norm();
  report.relative_residual = b_norm > 0.0 ? residual_.norm() / b_norm : residual_.norm();
  report.ok = std::isfinite(report.relative_residual);
  return report;
}

}  // namespace surgical_sim::core
