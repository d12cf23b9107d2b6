#include "surgical_sim/core/haptics/haptic_loop.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

HapticLoop::HapticLoop(const HapticRendererConfig& config, std::size_t period_ring_size,
                       int realtime_priority)
    : renderer_(config),
      period_(
          std::chrono::nanoseconds(static_cast<std::int64_t>(std::llround(1e9 / config.rate_hz)))),
      device_config_(config.device),
      ring_size_(period_ring_size),
      realtime_priority_(realtime_priority) {
  requireInRange("haptics.period_ring_size", static_cast<double>(period_ring_size), 16.0, 1e7, "");
  requireInRange("haptics.realtime_priority", realtime_priority, 0.0, 99.0, "");
  period_ring_.reset(new std::atomic<double>[ring_size_]);
  for (std::size_t i = 0; i < ring_size_; ++i) period_ring_[i].store(0.0);
}

HapticLoop::~HapticLoop() { stop(); }

void HapticLoop::start() {
  if (running_.load()) return;
  ticks_ = 0;
  missed_ = 0;
  period_count_ = 0;
  max_deviation_ = 0.0;
  stop_requested_ = false;
  renderer_.reset();
  running_ = true;
  thread_ = std::thread(&HapticLoop::run, this);
  realtime_granted_ = false;
  if (realtime_priority_ > 0) {
    sched_param param{};
    param.sched_priority = realtime_priority_;
    realtime_granted_ = pthread_setschedparam(thread_.native_handle(), SCHED_FIFO, &param) == 0;
  }
}

void HapticLoop::stop() {
  if (!thread_.joinable()) return;
  stop_requested_ = true;
  thread_.join();
  running_ = false;
}

void HapticLoop::setJointCommand(const TrocarJointVector& q) {
  std::lock_guard<std::mutex> lock(command_mutex_);
  command_ = q;
  command_fresh_ = true;
}

void HapticLoop::setContactModel(const LocalContactSample& sample) {
  std::lock_guard<std::mutex> lock(contact_mutex_);
  contact_ = sample;
  contact_fresh_ = true;
}

void HapticLoop::setPitchYawLimits(double pitch_limit, double yaw_limit) {
  std::lock_guard<std::mutex> lock(limits_mutex_);
  TrocarDeviceConfig candidate = device_config_;
  candidate.pitch_limit = pitch_limit;
  candidate.yaw_limit = yaw_limit;
  validateTrocarDeviceConfig(candidate);
  device_config_ = candidate;
  limits_fresh_ = true;
}

void HapticLoop::pitchYawLimits(double& pitch_limit, double& yaw_limit) const {
  std::lock_guard<std::mutex> lock(limits_mutex_);
  pitch_limit = device_config_.pitch_limit;
  yaw_limit = device_config_.yaw_limit;
}

HapticOutput HapticLoop::latestOutput() const {
  std::lock_guard<std::mutex> lock(output_mutex_);
  return output_;
}

double HapticLoop::now() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

LoopStatistics HapticLoop::statistics() const {
  LoopStatistics stats;
  stats.ticks = ticks_.load();
  stats.missed_ticks = missed_.load();
  stats.nominal_period = std::chrono::duration<double>(period_).count();
  stats.max_deviation = max_deviation_.load();
  const std::uint64_t count = period_count_.load();
  stats.samples = static_cast<std::size_t>(std::min<std::uint64_t>(count, ring_size_));
  if (stats.samples == 0) return stats;
  std::vector<double> periods(stats.samples);
  for (std::size_t i = 0; i < stats.samples; ++i) periods[i] = period_ring_[i].load();
  double sum = 0.0;
  for (double p : periods) sum += p;
  stats.period_mean = sum / static_cast<double>(stats.samples);
  stats.period_max = *std::max_element(periods.begin(), periods.end());
  const std::size_t k =
      std::min(stats.samples - 1, static_cast<std::size_t>(std::ceil(0.99 * stats.samples)) - 1);
  std::nth_element(periods.begin(), periods.begin() + k, periods.end());
  stats.period_p99 = periods[k];
  return stats;
}

void HapticLoop::run() noexcept {
  using Clock = std::chrono::steady_clock;
  const double nominal = std::chrono::duration<double>(period_).count();
  TrocarJointVector command = TrocarJointVector::Zero();
  LocalContactSample contact;
  Clock::time_point deadline = Clock::now();
  Clock::time_point previous_start{};
  bool first = true;
  double max_deviation = 0.0;
  std::uint64_t period_count = 0;

  while (!stop_requested_.load(std::memory_order_relaxed)) {
    std::this_thread::sleep_until(deadline);
    const Clock::time_point start = Clock::now();

    // Timing: period since the previous tick, missed deadlines.
    if (!first) {
      const double period = std::chrono::duration<double>(start - previous_start).count();
      period_ring_[period_count % ring_size_].store(period, std::memory_order_relaxed);
      ++period_count;
      period_count_.store(period_count, std::memory_order_relaxed);
      max_deviation = std::max(max_deviation, std::abs(period - nominal));
      max_deviation_.store(max_deviation, std::memory_order_relaxed);
    }
    first = false;
    previous_start = start;
    const auto lateness = start - deadline;
    if (lateness >= period_) {
      const auto skipped = static_cast<std::uint64_t>(lateness / period_);
      missed_.fetch_add(skipped, std::memory_order_relaxed);
      deadline += period_ * static_cast<std::int64_t>(skipped);
    }
    deadline += period_;

    // Inputs: take them only if the writer is not holding the lock.
    if (command_mutex_.try_lock()) {
      if (command_fresh_) {
        command = command_;
        command_fresh_ = false;
      }
      command_mutex_.unlock();
    }
    if (contact_mutex_.try_lock()) {
      if (contact_fresh_) {
        contact = contact_;
        contact_fresh_ = false;
        renderer_.setContactSample(contact);
      }
      contact_mutex_.unlock();
    }

    if (limits_mutex_.try_lock()) {
      // Validated by setPitchYawLimits, so this cannot throw.
      if (limits_fresh_)
        renderer_.device().setPitchYawLimits(device_config_.pitch_limit, device_config_.yaw_limit);
      limits_fresh_ = false;
      limits_mutex_.unlock();
    }
    if (reset_requested_.exchange(false)) renderer_.reset();

    const double now_s = std::chrono::duration<double>(start.time_since_epoch()).count();
    const HapticOutput& out = renderer_.update(command, now_s);
    if (output_mutex_.try_lock()) {
      output_ = out;
      output_mutex_.unlock();
    }
    ticks_.fetch_add(1, std::memory_order_relaxed);
  }
}

}  // namespace surgical_sim::core
