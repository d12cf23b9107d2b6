#include "surgical_sim/core/solve/background_cholesky_pcg_solver.h"

#include <algorithm>
#include <new>
#include <utility>
#include <vector>

#include "surgical_sim/core/solve/single_thread_blas.h"

namespace surgical_sim::core {
namespace {

constexpr int kMaxBackoffExponent = 20;  // 2^19 calls: beyond any refresh_interval in use

/// Same dimensions and nonzero structure (both compressed).
bool samePattern(const Eigen::SparseMatrix<double>& a, const Eigen::SparseMatrix<double>& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && a.nonZeros() == b.nonZeros() &&
         std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1, b.outerIndexPtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr());
}

}  // namespace

BackgroundCholeskyPcgSolver::BackgroundCholeskyPcgSolver(const PcgSettings& settings)
    : settings_(settings) {
  validatePcgSettings(settings);
  factor_and_tail_ = [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    return applyFactorAndTail(r, z);
  };
  worker_ = std::thread(&BackgroundCholeskyPcgSolver::runWorker, this);
}

BackgroundCholeskyPcgSolver::~BackgroundCholeskyPcgSolver() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

std::string BackgroundCholeskyPcgSolver::name() const { return "pcg_cholesky_background"; }

void BackgroundCholeskyPcgSolver::runWorker() {
  useSingleThreadBlas();  // the OpenMP thread count is per thread: limit this one too
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [this] { return stop_ || worker_state_ == WorkerState::Busy; });
    if (stop_) return;
    FactorSlot& spare = slots_[static_cast<size_t>(1 - current_)];
    lock.unlock();
    try {
      factorizeInto(spare, job_matrix_, job_pattern_, job_values_);
    } catch (const std::bad_alloc&) {
      spare.valid = false;
      spare.pattern = 0;  // the analysis may be incomplete
    }
    lock.lock();
    worker_state_ = WorkerState::Done;
    changed_.notify_all();
  }
}

void BackgroundCholeskyPcgSolver::factorizeInto(FactorSlot& slot,
                                                const Eigen::SparseMatrix<double>& A,
                                                std::uint64_t pattern, std::uint64_t values) {
  if (slot.pattern != pattern) {
    slot.cholmod.analyzePattern(A);
    slot.pattern = pattern;
    slot.rows = A.rows();
  }
  slot.valid = slot.cholmod.factorize(A);
  slot.values = values;
}

void BackgroundCholeskyPcgSolver::analyzePattern(const Eigen::SparseMatrix<double>& A) {
  factorized_ = false;
  Eigen::SparseMatrix<double> pattern = A;
  pattern.makeCompressed();
  if (pattern_ != 0 && samePattern(pattern, matrix_)) return;
  // Only a growing pattern keeps the meaning of the first unknowns.
  if (pattern.rows() < matrix_.rows()) first_usable_values_ = values_ + 1;
  matrix_ = std::move(pattern);
  ++pattern_;
  max_iterations_ = pcgIterationCap(settings_, matrix_.rows());
  work_.resize(matrix_.rows());
}

bool BackgroundCholeskyPcgSolver::usable(const FactorSlot& slot) const {
  return slot.valid && slot.rows <= matrix_.rows() && slot.values >= first_usable_values_;
}

bool BackgroundCholeskyPcgSolver::adoptRefresh() {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (worker_state_ != WorkerState::Done) return false;
  worker_state_ = WorkerState::Idle;
  const FactorSlot& spare = slots_[static_cast<size_t>(1 - current_)];
  if (!usable(spare) || (usable(current()) && spare.values <= current().values)) return false;
  current_ = 1 - current_;
  ++background_refreshes_;
  return true;
}

void BackgroundCholeskyPcgSolver::startRefreshIfDue() {
  const bool due = calls_since_refresh_ >= settings_.refresh_interval || refresh_requested_ ||
                   current().pattern != pattern_;
  if (!due) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  if (worker_state_ != WorkerState::Idle) return;
  job_matrix_ = matrix_;
  job_pattern_ = pattern_;
  job_values_ = values_;
  worker_state_ = WorkerState::Busy;
  calls_since_refresh_ = 0;
  refresh_requested_ = false;
  changed_.notify_all();
}

bool BackgroundCholeskyPcgSolver::factorizeSynchronously() {
  ++synchronous_factorizations_;
  calls_since_refresh_ = 0;
  refresh_requested_ = false;
  factorizeInto(current(), matrix_, pattern_, values_);
  return current().valid;
}

void BackgroundCholeskyPcgSolver::buildInterim() {
  const FactorSlot& factor = current();
  const Eigen::Index rows = factor.rows;
  const Eigen::Index head = rows < matrix_.rows() ? rows : 0;
  head_rhs_.resize(head);
  head_solution_.resize(head);
  tail_.resize(rows, matrix_.rows());
  tail_ok_ = tail_.build(matrix_);
  local_ok_ = true;
  if (factor.pattern == pattern_) return;
  if (local_pattern_ != pattern_ || local_factor_ != factor.values) {
    std::vector<int> unknowns =
        changedPatternUnknowns(matrix_, factor.cholmod.analysedMatrix(), kLocalRings);
    if (static_cast<Eigen::Index>(unknowns.size()) > matrix_.rows() / 2) unknowns.clear();
    local_.setUnknowns(matrix_, std::move(unknowns));
    local_pattern_ = pattern_;
    local_factor_ = factor.values;
  }
  if (local_.active()) local_ok_ = local_.factorize(matrix_);
}

bool BackgroundCholeskyPcgSolver::factorize(const Eigen::SparseMatrix<double>& A) {
  factorized_ = false;
  if (!copyValuesOfSamePattern(A, matrix_)) return false;
  ++values_;
  if (!matrix_.coeffs().allFinite()) return false;
  adoptRefresh();
  if (usable(current()) && synchronous_calls_left_ == 0) {
    startRefreshIfDue();
  } else {
    synchronous_calls_left_ = std::max(0, synchronous_calls_left_ - 1);
    if (!factorizeSynchronously()) return false;
  }
  ++calls_since_refresh_;
  buildInterim();
  factorized_ = tail_ok_ && local_ok_;
  return factorized_;
}

bool BackgroundCholeskyPcgSolver::applyFactorAndTail(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  FactorSlot& factor = current();
  if (factor.rows == r.size()) return factor.cholmod.precondition(r, z);
  head_rhs_ = r.head(factor.rows);
  if (!factor.cholmod.precondition(head_rhs_, head_solution_)) return false;
  z.head(factor.rows) = head_solution_;
  tail_.apply(r, z);
  return true;
}

bool BackgroundCholeskyPcgSolver::applyPreconditioner(const Eigen::VectorXd& r,
                                                      Eigen::VectorXd& z) {
  if (!tail_ok_ || !local_ok_) return false;
  if (current().pattern != pattern_ && local_.active()) {
    return local_.apply(matrix_, r, z, factor_and_tail_);
  }
  return applyFactorAndTail(r, z);
}

LinearSolveReport BackgroundCholeskyPcgSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!factorized_ || b.size() != matrix_.rows() || x.size() != b.size() || !b.allFinite()) {
    return {};
  }
  const PreconditionerApply precondition = [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    return applyPreconditioner(r, z);
  };
  const bool exact = current().values == values_;
  const int budget = exact ? max_iterations_ : std::min(max_iterations_, kFallbackIterations);
  LinearSolveReport report = preconditionedConjugateGradient(
      matrix_, b, x, budget, settings_.relative_tolerance, precondition, work_);
  if (report.ok || exact) {
    refresh_requested_ = refresh_requested_ || report.iterations > kRefreshIterations;
    if (!exact) fallback_streak_ = 0;
    return report;
  }
  // Failed with the factor of an older matrix (or the interim preconditioner): factorize this
  // matrix and solve again from the last iterate; back off from old factors for 1, 2, 4, ...
  // calls (at most refresh_interval) while they keep failing.
  fallback_streak_ = std::min(fallback_streak_ + 1, kMaxBackoffExponent);
  synchronous_calls_left_ = std::min(1 << (fallback_streak_ - 1), settings_.refresh_interval);
  const int first_iterations = report.iterations;
  factorized_ = factorizeSynchronously();
  if (!factorized_) return report;
  buildInterim();
  report = preconditionedConjugateGradient(matrix_, b, x, max_iterations_,
                                           settings_.relative_tolerance, precondition, work_);
  report.iterations += first_iterations;
  return report;
}

void BackgroundCholeskyPcgSolver::waitForRefresh() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return worker_state_ != WorkerState::Busy; });
}

}  // namespace surgical_sim::core
