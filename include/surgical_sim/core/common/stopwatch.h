#pragma once

#include <chrono>
#include <type_traits>

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

/// Calls f(), adds its wall time [s] to `seconds` and returns what f returns. Allocation-free.
template <class F>
auto timed(double& seconds, F&& f) {
  const Stopwatch watch;
  if constexpr (std::is_void_v<decltype(f())>) {
    f();
    seconds += watch.seconds();
  } else {
    auto result = f();
    seconds += watch.seconds();
    return result;
  }
}

}  // namespace surgical_sim::core
