// ThreadPool runs every task of a run exactly once, also when two threads run at once;
// LazyThreadPool starts its workers only with its first parallel run; defaultThreadCount reads
// SURGICAL_SIM_THREADS and rejects bad values by name.
#include "surgical_sim/core/common/thread_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace surgical_sim::core {
namespace {

/// Sets SURGICAL_SIM_THREADS for the scope and restores the previous value.
class ThreadsVariable {
 public:
  explicit ThreadsVariable(const char* value) {
    if (const char* old = std::getenv(kName)) old_ = std::string(old);
    if (value == nullptr) {
      unsetenv(kName);
    } else {
      setenv(kName, value, 1);
    }
  }
  ~ThreadsVariable() {
    if (old_) {
      setenv(kName, old_->c_str(), 1);
    } else {
      unsetenv(kName);
    }
  }

 private:
  static constexpr const char* kName = "SURGICAL_SIM_THREADS";
  std::optional<std::string> old_;
};

/// Threads of this process (Linux: entries of /proc/self/task).
long processThreads() {
  const std::filesystem::directory_iterator tasks("/proc/self/task");
  return std::distance(std::filesystem::begin(tasks), std::filesystem::end(tasks));
}

TEST(ThreadPool, RunsEveryTaskExactlyOnce) {
  for (int threads = 1; threads <= 3; ++threads) {
    ThreadPool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    for (int count : {0, 1, 2, 7, 100}) {
      std::vector<std::atomic<int>> runs(static_cast<size_t>(count));
      for (auto& r : runs) r = 0;
      pool.run(count, [&](int i) { ++runs[static_cast<size_t>(i)]; });
      for (int i = 0; i < count; ++i) EXPECT_EQ(runs[static_cast<size_t>(i)], 1) << i;
    }
  }
}

TEST(ThreadPool, TwoCallersAtOnceEachGetAllTheirTasks) {
  ThreadPool pool(2);
  constexpr int kRuns = 200;
  constexpr int kTasks = 16;
  std::atomic<int> first{0};
  std::atomic<int> second{0};
  std::thread other([&] {
    for (int r = 0; r < kRuns; ++r) pool.run(kTasks, [&](int) { ++second; });
  });
  for (int r = 0; r < kRuns; ++r) pool.run(kTasks, [&](int) { ++first; });
  other.join();
  EXPECT_EQ(first, kRuns * kTasks);
  EXPECT_EQ(second, kRuns * kTasks);
}

TEST(ThreadPool, RejectsAThreadCountOutOfRange) {
  EXPECT_THROW(ThreadPool(0), std::invalid_argument);
  EXPECT_THROW(ThreadPool(kMaxThreads + 1), std::invalid_argument);
}

TEST(LazyThreadPool, StartsItsWorkersWithTheFirstParallelRunOnly) {
  const long before = processThreads();
  LazyThreadPool pool(3);
  EXPECT_EQ(pool.threads(), 3);
  std::atomic<int> runs{0};
  pool.run(1, [&](int) { ++runs; });
  EXPECT_EQ(processThreads(), before);  // one task: on the caller, nothing started
  constexpr int kTasks = 40;
  for (int r = 0; r < 3; ++r) pool.run(kTasks, [&](int) { ++runs; });
  EXPECT_EQ(runs, 1 + 3 * kTasks);
  EXPECT_EQ(processThreads(), before + 2);  // started once, kept for later runs
}

TEST(LazyThreadPool, OneThreadNeverStartsAWorker) {
  const long before = processThreads();
  LazyThreadPool pool(1);
  std::vector<int> order;
  pool.run(5, [&](int i) { order.push_back(i); });
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(processThreads(), before);
  EXPECT_THROW(LazyThreadPool(0), std::invalid_argument);
  EXPECT_THROW(LazyThreadPool(kMaxThreads + 1), std::invalid_argument);
}

TEST(DefaultElementThreads, ReadsTheEnvironmentVariable) {
  {
    const ThreadsVariable set("3");
    EXPECT_EQ(defaultThreadCount(), 3);
  }
  const ThreadsVariable unset(nullptr);
  EXPECT_GE(defaultThreadCount(), 1);
  EXPECT_LE(defaultThreadCount(), 2);
}

TEST(DefaultElementThreads, NamesTheVariableValueAndRangeOfABadValue) {
  for (const char* bad : {"0", "-1", "abc", "2x", "", "65"}) {
    const ThreadsVariable set(bad);
    try {
      defaultThreadCount();
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("SURGICAL_SIM_THREADS"), std::string::npos) << message;
      EXPECT_NE(message.find(std::string("'") + bad + "'"), std::string::npos) << message;
      EXPECT_NE(message.find("[1, 64]"), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace surgical_sim::core
