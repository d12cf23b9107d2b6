#pragma once

#include <chrono>

namespace surgical_sim::core {

/// Monotonic wall-clock stopwatch (steady_clock). Allocation-free.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  void restart() { start_ = std::chrono::steady_clock::now(); }
  /// Elapsed time since construction or the last restart() [s].
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  /// Elapsed time [ms].
  double milliseconds() const { return 1e3 * seconds(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace surgical_sim::core
