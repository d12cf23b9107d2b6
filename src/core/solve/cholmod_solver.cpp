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
  analyzeWithOrdering(A, nullptr);
}

void CholmodSolver::analyzeChangedPattern(const Eigen::SparseMatrix<double>& A) {
  if (factor_ == nullptr || static_cast<Eigen::Index>(factor_->n) != A.rows() ||
      A.rows() != A.cols()) {
    analyzePattern(A);
    return;
  }
  const auto* perm = static_cast<const int*>(factor_->Perm);
  std::vector<int> ordering(perm, perm + factor_->n);
  analyzeWithOrdering(A, &ordering);
  if (factor_ == nullptr || fill() > kMaxKeptOrderingFill * ordered_fill_) analyzePattern(A);
}

void CholmodSolver::analyzeWithOrdering(const Eigen::SparseMatrix<double>& A,
                                        std::vector<int>* ordering) {
  releaseFactor();
  matrix_ = A;
  matrix_.makeCompressed();
  residual_.resize(A.rows());
  cholmod_sparse view = viewOf(matrix_);
  if (ordering == nullptr) {
    factor_ = cholmod_analyze(&view, &common_);
    ++orderings_;
    ordered_fill_ = fill();
    return;
  }
  const int method = common_.method[0].ordering;
  common_.method[0].ordering = CHOLMOD_GIVEN;
  factor_ = cholmod_analyze_p(&view, ordering->data(), nullptr, 0, &common_);
  common_.method[0].ordering = method;
}

double CholmodSolver::fill() const {
  return factorNonzeros() / std::max<double>(1.0, matrix_.nonZeros());
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
