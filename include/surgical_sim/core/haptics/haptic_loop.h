#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>

#include "surgical_sim/core/haptics/haptic_renderer.h"

namespace surgical_sim::core {

/// Timing statistics of HapticLoop (H1). Periods are measured between consecutive tick starts.
struct LoopStatistics {
  std::uint64_t ticks = 0;         ///< ticks executed
  std::uint64_t missed_ticks = 0;  ///< deadlines skipped because the loop woke >= 1 period late
  std::size_t samples = 0;         ///< periods in the ring used for mean / p99
  double nominal_period = 0.0;     ///< 1 / rate_hz [s]
  double period_mean = 0.0;        ///< mean period over the ring [s]
  double period_p99 = 0.0;         ///< 99th percentile of the period over the ring [s]
  double period_max = 0.0;         ///< longest period over the ring [s]
  double max_deviation = 0.0;      ///< max |period - nominal| since start() [s]
};

/// The 1 kHz device loop: a thread that wakes at absolute deadlines (steady_clock, sleep_until),
/// reads the latest operator joint command and contact model (try-locked double buffers: the loop
/// never blocks on a writer, it keeps the previous value when the writer holds the lock), runs
/// HapticRenderer::update() and publishes the output (try-locked) and the timing statistics
/// (lock-free ring of periods). Inside the loop nothing allocates and nothing throws. A deadline
/// missed by one period or more is counted and skipped (the schedule stays absolute).
///
/// Clock: now() = steady_clock seconds; contact-model stamps must use it.
class HapticLoop {
 public:
  /// @param period_ring_size number of periods kept for mean / p99 [-], in [16, 1e7].
  /// @param realtime_priority SCHED_FIFO priority requested for the loop thread, in [0, 99];
  /// 0 keeps the default scheduler. A refused request is reported by realtimeGranted().
  /// @throws std::invalid_argument if config, period_ring_size or realtime_priority is invalid.
  HapticLoop(const HapticRendererConfig& config, std::size_t period_ring_size,
             int realtime_priority = 0);
  ~HapticLoop();
  HapticLoop(const HapticLoop&) = delete;
  HapticLoop& operator=(const HapticLoop&) = delete;

  /// Starts the thread (no-op if running). Statistics restart.
  void start();
  /// Stops and joins the thread (no-op if stopped).
  void stop();
  bool running() const { return running_.load(); }
  /// True if the SCHED_FIFO priority was requested and granted at the last start().
  bool realtimeGranted() const { return realtime_granted_.load(); }

  /// Operator joint positions q (5x1) [rad, m] (e.g. from trocar/joint_command). Blocks briefly.
  void setJointCommand(const TrocarJointVector& q);
  /// New local contact model, stamped on now()'s clock. Blocks briefly.
  void setContactModel(const LocalContactSample& sample);
  /// New symmetric pitch / yaw ranges +-limit [rad] (service trocar/set_limits), applied by the
  /// loop at its next tick. Blocks briefly.
  /// @throws std::invalid_argument naming "trocar.pitch_limit" / "trocar.yaw_limit" if a limit is
  /// outside [0, 70] deg; the loop is unchanged then.
  void setPitchYawLimits(double pitch_limit, double yaw_limit);
  /// Current pitch / yaw limits [rad] (the last accepted setPitchYawLimits, or the config's).
  void pitchYawLimits(double& pitch_limit, double& yaw_limit) const;
  /// Asks the loop to restart velocity estimation, coupling proxy and passivity observer
  /// (HapticRenderer::reset) at its next tick (service trocar/home). Never blocks.
  void requestReset() { reset_requested_.store(true); }

  /// Latest tick output (copy).
  HapticOutput latestOutput() const;
  /// Timing statistics (copies the ring; call from a non-real-time thread).
  LoopStatistics statistics() const;
  /// The loop's clock [s] (steady_clock since its epoch).
  double now() const;

 private:
  void run() noexcept;

  HapticRenderer renderer_;
  std::chrono::nanoseconds period_;

  mutable std::mutex command_mutex_;
  TrocarJointVector command_ = TrocarJointVector::Zero();
  bool command_fresh_ = false;

  mutable std::mutex contact_mutex_;
  LocalContactSample contact_;
  bool contact_fresh_ = false;

  mutable std::mutex limits_mutex_;
  TrocarDeviceConfig device_config_;  ///< accepted limits (validated copy of the device config)
  bool limits_fresh_ = false;
  std::atomic<bool> reset_requested_{false};

  mutable std::mutex output_mutex_;
  HapticOutput output_;

  std::size_t ring_size_;
  std::unique_ptr<std::atomic<double>[]> period_ring_;
  std::atomic<std::uint64_t> ticks_{0};
  std::atomic<std::uint64_t> missed_{0};
  std::atomic<std::uint64_t> period_count_{0};
  std::atomic<double> max_deviation_{0.0};

  int realtime_priority_;
  std::atomic<bool> realtime_granted_{false};
  std::atomic<bool> running_{false};
  std::atomic<bool> stop_requested_{false};
  std::thread thread_;
};

}  // namespace surgical_sim::core
