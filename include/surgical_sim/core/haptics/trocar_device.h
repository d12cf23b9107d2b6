#pragma once

#include "surgical_sim/core/haptics/trocar_device_config.h"
#include "surgical_sim/core/haptics/trocar_joints.h"

namespace surgical_sim::core {

/// Result of TrocarDevice::saturate.
struct EffortSaturation {
  double scale = 1.0;       ///< factor applied to the whole effort vector [-], in [0, 1]
  bool saturated = false;   ///< true if scale < 1 (some joint exceeded its effort limit)
  bool non_finite = false;  ///< true if the input held NaN/Inf (the output is then zero)
};

/// Model of the 5-DoF active trocar's actuation and sensing: joint limits, encoder quantization,
/// force-to-effort mapping, direction-preserving saturation, motor torques, transmission friction.
/// Everything except the constructor and setPitchYawLimits() is noexcept and allocation-free.
class TrocarDevice {
 public:
  /// @throws std::invalid_argument if the configuration is invalid (validateTrocarDeviceConfig).
  explicit TrocarDevice(const TrocarDeviceConfig& config);

  const TrocarDeviceConfig& config() const { return config_; }

  /// Sets the symmetric pitch and yaw ranges (+-limit) [rad] (service trocar/set_limits).
  /// @throws std::invalid_argument naming "trocar.pitch_limit" / "trocar.yaw_limit" if a limit is
  /// outside [0, 70] deg; the device is unchanged then.
  void setPitchYawLimits(double pitch_limit, double yaw_limit);

  /// Clamps q (5x1) in place to the joint limits: pitch/yaw to +-limit [rad], insertion to
  /// [0, insertion_max] [m], grip to [0, grip_max] [rad]; spin is wrapped to [-pi, pi) [rad]
  /// (continuous joint, wrapping is not clamping). Non-finite entries become the range centre
  /// (spin 0). Returns true if any joint was clamped or non-finite.
  bool clampToLimits(TrocarJointVector& q) const noexcept;

  /// Encoder reading of q (5x1): clamped/wrapped as clampToLimits, then rounded to the nearest
  /// multiple of each joint's encoder_step (quantization error <= step / 2).
  TrocarJointVector quantize(const TrocarJointVector& q) const noexcept;

  /// Joint efforts tau = J^T w (5x1: [N m] revolute, [N] insertion) that render the wrench
  /// w = [f; m] (6x1, [N; N m], applied to the tool at the tool tip, expressed in the Jacobian's
  /// frame) for the tool-tip Jacobian J (6x5, same frame). This is the virtual-work projection;
  /// it replaces the thesis' non-orthogonal decomposition (Chendeb eqs 5.4–5.10), which gives a
  /// non-zero spin torque for a force acting on the shaft line.
  static TrocarJointVector jointEfforts(const TrocarJacobian& J, const SpatialVector& w) noexcept;

  /// Direction-preserving saturation of tau (5x1) in place: the whole vector is scaled by
  /// min(1, min_i effort_limit_i / |tau_i|), so every |tau_i| <= effort_limit_i and the rendered
  /// direction is kept. A non-finite input is replaced by zero and flagged.
  EffortSaturation saturate(TrocarJointVector& tau) const noexcept;

  /// Motor torques [N m] (5x1) for joint efforts tau: tau_i / gear_ratio_i (ideal transmission).
  TrocarJointVector motorTorques(const TrocarJointVector& tau) const noexcept;

  /// Transmission friction efforts at joint velocities qdot (5x1, [rad/s] or [m/s]):
  /// -(viscous qdot + coulomb sign(qdot)), [N m] or [N]; they oppose the motion.
  TrocarJointVector frictionEfforts(const TrocarJointVector& qdot) const noexcept;

  /// Rotor inertia reflected to each joint, rotor_inertia * gear_ratio^2 (5x1): [kg m^2] for the
  /// revolute joints, [kg] for insertion.
  TrocarJointVector reflectedInertia() const noexcept;

 private:
  TrocarDeviceConfig config_;
};

}  // namespace surgical_sim::core
