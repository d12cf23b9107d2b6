#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace surgical_sim::core {

/// Largest thread count accepted for the element loops and triangular solves [-].
constexpr int kMaxThreads = 64;

/// Threads for the element loops of the tissue models (GroupSchedule) and the preconditioner's
/// triangular solves (SinglePrecisionCholesky): the environment variable
/// SURGICAL_SIM_THREADS (an integer in [1, kMaxThreads]) if set, else the hardware threads
/// capped at 2.
/// @throws std::invalid_argument naming SURGICAL_SIM_THREADS, its value and the allowed range if it
///         is set to anything else.
int defaultThreadCount();

/// A fixed set of worker threads that run the tasks of one run() call with the calling thread.
/// Which thread runs which task is not fixed: callers make results independent of it (tasks that
/// write disjoint data, reductions in task order). run() from a second thread while a run is in
/// progress executes its tasks on that thread alone (same results, no parallelism). Not copyable.
class ThreadPool {
 public:
  /// @param threads threads taking part in a run, the caller included, in [1, kMaxThreads]
  ///        (fewer if the system cannot start them: threads() tells)
  /// @throws std::invalid_argument naming "threads" if out of range.
  explicit ThreadPool(int threads);
  /// Stops and joins the workers.
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }
  /// Runs task(i) for every i in [0, count) and returns when all have finished. A task must not
  /// throw and must not call run() on the same pool.
  void run(int count, const std::function<void(int)>& task);

 private:
  void work();
  /// Takes and runs tasks of the current run until none is left.
  void drain();

  std::vector<std::thread> workers_;
  std::mutex run_mutex_;  ///< held by the caller of a parallel run
  std::mutex mutex_;      ///< guards the fields below
  std::condition_variable start_;
  std::condition_variable finished_;
  const std::function<void(int)>* task_ = nullptr;
  int count_ = 0;
  int next_ = 0;  ///< next task index to take
  int done_ = 0;  ///< tasks finished
  std::uint64_t generation_ = 0;
  bool stop_ = false;
};

/// A ThreadPool whose workers start at the first run() with more than one task: an owner whose
/// loops never run in parallel holds no idle threads. Runs are those of ThreadPool (same
/// thread-safety, same results). Not copyable.
class LazyThreadPool {
 public:
  /// @param threads threads of a parallel run, the caller included, in [1, kMaxThreads]
  /// @throws std::invalid_argument naming "threads" if out of range.
  explicit LazyThreadPool(int threads);
  LazyThreadPool(const LazyThreadPool&) = delete;
  LazyThreadPool& operator=(const LazyThreadPool&) = delete;

  /// Threads requested (a started pool may hold fewer: ThreadPool::threads()).
  int threads() const { return threads_; }
  /// ThreadPool::run; a run of one task (or with threads() == 1) runs on the caller and starts
  /// nothing.
  void run(int count, const std::function<void(int)>& task);

 private:
  int threads_;
  std::once_flag started_;
  std::unique_ptr<ThreadPool> pool_;  ///< set once, by the first parallel run
};

}  // namespace surgical_sim::core
