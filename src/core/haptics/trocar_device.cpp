#include "surgical_sim/core/haptics/trocar_device.h"

#include <algorithm>
#include <cmath>

namespace surgical_sim::core {
namespace {

double wrapToPi(double angle) {
  return angle - 2.0 * M_PI * std::floor((angle + M_PI) / (2.0 * M_PI));
}

/// Clamps value to [lo, hi]; a non-finite value becomes the centre. Sets clamped if changed.
double clampJoint(double value, double lo, double hi, bool& clamped) {
  if (!std::isfinite(value)) {
    clamped = true;
    return 0.5 * (lo + hi);
  }
  if (value < lo || value > hi) {
    clamped = true;
    return std::clamp(value, lo, hi);
  }
  return value;
}

}  // namespace

TrocarDevice::TrocarDevice(const TrocarDeviceConfig& config) : config_(config) {
  validateTrocarDeviceConfig(config_);
}

void TrocarDevice::setPitchYawLimits(double pitch_limit, double yaw_limit) {
  TrocarDeviceConfig candidate = config_;
  candidate.pitch_limit = pitch_limit;
  candidate.yaw_limit = yaw_limit;
  validateTrocarDeviceConfig(candidate);
  config_ = candidate;
}

bool TrocarDevice::clampToLimits(TrocarJointVector& q) const noexcept {
  bool clamped = false;
  q[kTrocarPitch] = clampJoint(q[kTrocarPitch], -config_.pitch_limit, config_.pitch_limit, clamped);
  q[kTrocarYaw] = clampJoint(q[kTrocarYaw], -config_.yaw_limit, config_.yaw_limit, clamped);
  if (std::isfinite(q[kTrocarSpin])) {
    q[kTrocarSpin] = wrapToPi(q[kTrocarSpin]);
  } else {
    q[kTrocarSpin] = 0.0;
    clamped = true;
  }
  q[kTrocarInsertion] = clampJoint(q[kTrocarInsertion], 0.0, config_.insertion_max, clamped);
  q[kTrocarGrip] = clampJoint(q[kTrocarGrip], 0.0, config_.grip_max, clamped);
  return clamped;
}

TrocarJointVector TrocarDevice::quantize(const TrocarJointVector& q) const noexcept {
  TrocarJointVector reading = q;
  clampToLimits(reading);
  for (int j = 0; j < kTrocarJointCount; ++j) {
    const double step = config_.drives[j].encoder_step;
    reading[j] = std::round(reading[j] / step) * step;
  }
  return reading;
}

TrocarJointVector TrocarDevice::jointEfforts(const TrocarJacobian& J,
                                             const SpatialVector& w) noexcept {
  return J.transpose() * w;
}

EffortSaturation TrocarDevice::saturate(TrocarJointVector& tau) const noexcept {
  EffortSaturation result;
  if (!tau.allFinite()) {
    tau.setZero();
    result.non_finite = true;
    return result;
  }
  for (int j = 0; j < kTrocarJointCount; ++j) {
    const double magnitude = std::abs(tau[j]);
    const double limit = config_.drives[j].effort_limit;
    if (magnitude > limit) result.scale = std::min(result.scale, limit / magnitude);
  }
  if (result.scale < 1.0) {
    tau *= result.scale;
    result.saturated = true;
  }
  return result;
}

TrocarJointVector TrocarDevice::motorTorques(const TrocarJointVector& tau) const noexcept {
  TrocarJointVector motor;
  for (int j = 0; j < kTrocarJointCount; ++j) motor[j] = tau[j] / config_.drives[j].gear_ratio;
  return motor;
}

TrocarJointVector TrocarDevice::frictionEfforts(const TrocarJointVector& qdot) const noexcept {
  TrocarJointVector friction;
  for (int j = 0; j < kTrocarJointCount; ++j) {
    const TrocarJointDrive& d = config_.drives[j];
    const double sign = qdot[j] > 0.0 ? 1.0 : (qdot[j] < 0.0 ? -1.0 : 0.0);
    friction[j] = -(d.viscous_friction * qdot[j] + d.coulomb_friction * sign);
  }
  return friction;
}

TrocarJointVector TrocarDevice::reflectedInertia() const noexcept {
  TrocarJointVector inertia;
  for (int j = 0; j < kTrocarJointCount; ++j) {
    const TrocarJointDrive& d = config_.drives[j];
    inertia[j] = d.rotor_inertia * d.gear_ratio * d.gear_ratio;
  }
  return inertia;
}

}  // namespace surgical_sim::core
