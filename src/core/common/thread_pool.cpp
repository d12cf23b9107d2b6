#include "surgical_sim/core/common/thread_pool.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <system_error>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

int defaultThreadCount() {
  const char* text = std::getenv("SURGICAL_SIM_THREADS");
  if (text == nullptr) {
    const auto hardware = static_cast<int>(std::thread::hardware_concurrency());
    return std::clamp(hardware, 1, 2);
  }
  const std::string value(text);
  size_t parsed = 0;
  int threads = 0;
  try {
    threads = std::stoi(value, &parsed);
  } catch (const std::exception&) {
    parsed = 0;
  }
  if (parsed == 0 || parsed != value.size() || threads < 1 || threads > kMaxThreads) {
    throw std::invalid_argument("SURGICAL_SIM_THREADS = '" + value +
                                "' is out of range: must be an integer in [1, " +
                                std::to_string(kMaxThreads) + "]");
  }
  return threads;
}

ThreadPool::ThreadPool(int threads) {
  requireInRange("threads", threads, 1, kMaxThreads, "");
  workers_.reserve(static_cast<size_t>(threads - 1));
  try {
    for (int i = 1; i < threads; ++i) workers_.emplace_back(&ThreadPool::work, this);
  } catch (const std::system_error&) {
    // Out of threads or memory (e.g. a memory-limited child process): run with those started.
  }
}

ThreadPool::~ThreadPool() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void ThreadPool::run(int count, const std::function<void(int)>& task) {
  std::unique_lock<std::mutex> run_lock(run_mutex_, std::try_to_lock);
  if (workers_.empty() || count <= 1 || !run_lock.owns_lock()) {
    for (int i = 0; i < count; ++i) task(i);
    return;
  }
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    task_ = &task;
    count_ = count;
    next_ = 0;
    done_ = 0;
    ++generation_;
  }
  start_.notify_all();
  drain();
  std::unique_lock<std::mutex> lock(mutex_);
  finished_.wait(lock, [this] { return done_ == count_; });
  task_ = nullptr;
}

void ThreadPool::work() {
  std::uint64_t seen = 0;
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    start_.wait(lock, [&] { return stop_ || generation_ != seen; });
    if (stop_) return;
    seen = generation_;
    lock.unlock();
    drain();
    lock.lock();
  }
}

void ThreadPool::drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (task_ != nullptr && next_ < count_) {
    const int i = next_++;
    const std::function<void(int)>& task = *task_;
    lock.unlock();
    task(i);
    lock.lock();
    if (++done_ == count_) finished_.notify_all();
  }
}

LazyThreadPool::LazyThreadPool(int threads) : threads_(threads) {
  requireInRange("threads", threads, 1, kMaxThreads, "");
}

void LazyThreadPool::run(int count, const std::function<void(int)>& task) {
  if (threads_ == 1 || count <= 1) {
    for (int i = 0; i < count; ++i) task(i);
    return;
  }
  std::call_once(started_, [this] { pool_ = std::make_unique<ThreadPool>(threads_); });
  pool_->run(count, task);
}

}  // namespace surgical_sim::core
