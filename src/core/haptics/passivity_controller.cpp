#include "surgical_sim/core/haptics/passivity_controller.h"

#include <algorithm>
#include <cmath>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

void validatePassivityControllerSettings(const PassivityControllerSettings& settings) {
  requirePositive("haptics.passivity.max_damping", settings.max_damping, "N s/m");
  requireNonNegative("haptics.passivity.min_speed", settings.min_speed, "m/s");
}

PassivityController::PassivityController(const PassivityControllerSettings& settings)
    : settings_(settings) {
  validatePassivityControllerSettings(settings_);
}

void PassivityController::reset() noexcept {
  energy_ = 0.0;
  damping_ = 0.0;
  dissipated_ = 0.0;
  held_force_.setZero();
}

Eigen::Vector3d PassivityController::step(const Eigen::Vector3d& force_W,
                                          const Eigen::Vector3d& v_W, double dt) noexcept {
  damping_ = 0.0;
  if (!force_W.allFinite() || !v_W.allFinite() || !(dt > 0.0) || !std::isfinite(dt)) {
    held_force_.setZero();
    return held_force_;
  }
  // Work done on the device port while the previous output was held.
  energy_ -= held_force_.dot(v_W) * dt;
  held_force_ = force_W;
  const double speed_sq = v_W.squaredNorm();
  if (!settings_.control_enabled || energy_ >= 0.0 ||
      speed_sq <= settings_.min_speed * settings_.min_speed) {
    return held_force_;
  }
  damping_ = std::min(-energy_ / (speed_sq * dt), settings_.max_damping);
  dissipated_ += damping_ * speed_sq * dt;
  held_force_ -= damping_ * v_W;
  return held_force_;
}

void PassivityController::setHeldForce(const Eigen::Vector3d& force_W) noexcept {
  if (force_W.allFinite()) {
    held_force_ = force_W;
  } else {
    held_force_.setZero();
  }
}

}  // namespace surgical_sim::core
