#pragma once

#include <deque>
#include <utility>

namespace surgical_sim::ros_layer {

/// Real-time factor of a running simulation: simulated time advanced over wall time elapsed,
/// over a sliding window of wall time. 1 = real time, 0.6 = the simulation runs at 60 % of
/// real time. No ROS communication (usable without roscore).
class RealTimeFactor {
 public:
  /// @throws std::invalid_argument if window_seconds is not finite and > 0.
  explicit RealTimeFactor(double window_seconds);

  /// Records that the simulation reached sim_time [s] at wall time wall_seconds [s]
  /// (non-decreasing); returns the factor over the window ending now, or 0 before two samples
  /// span any wall time. Samples older than the window (except the newest one before it) are
  /// dropped.
  double add(double wall_seconds, double sim_time);
  /// Forgets every sample (a reset or a pause: the next factor starts afresh).
  void clear() { samples_.clear(); }

 private:
  double window_;
  std::deque<std::pair<double, double>> samples_;  ///< (wall [s], sim [s])
};

}  // namespace surgical_sim::ros_layer
