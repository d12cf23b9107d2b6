#pragma once

#include <array>

#include "surgical_sim/core/haptics/trocar_joints.h"

namespace surgical_sim::core {

/// Motor + transmission of one trocar joint. Units follow the joint: revolute joints use [rad],
/// [N m]; the insertion joint uses [m], [N]. There are no silent defaults: a default-constructed
/// drive holds NaN and fails validation.
struct TrocarJointDrive {
  /// Transmission ratio d(motor angle)/d(joint coordinate) [rad/rad] or [rad/m], > 0. For the
  /// insertion friction rollers it is 1 / roller radius; motor torque = joint effort / ratio.
  double gear_ratio;
  double rotor_inertia;     ///< motor rotor inertia [kg m^2], >= 0
  double viscous_friction;  ///< joint-side viscous friction [N m s/rad] or [N s/m], >= 0
  double coulomb_friction;  ///< joint-side Coulomb friction [N m] or [N], >= 0
  double effort_limit;      ///< peak joint effort [N m] or [N], > 0
  double encoder_step;      ///< encoder quantization step at the joint [rad] or [m], > 0

  TrocarJointDrive();
};

/// Ranges validateTrocarDeviceConfig accepts for the joint limits.
inline constexpr double kTrocarMaxTiltLimitDeg = 70.0;  ///< pitch and yaw range +-limit [deg]
inline constexpr double kTrocarMaxInsertion = 0.30;     ///< insertion travel [m]
inline constexpr double kTrocarMaxGripDeg = 90.0;       ///< jaw opening [deg]

/// Configuration of the active trocar device model (Chendeb 2007 §5.3–5.4). The limits, effort
/// limits and joint frictions come from the trocar's URDF (makeTrocarDeviceConfig in
/// trocar_urdf.h), the rest of the drive data from TrocarMotor.
struct TrocarDeviceConfig {
  /// Drives indexed by TrocarJoint (pitch, yaw, spin, insertion, grip).
  std::array<TrocarJointDrive, kTrocarJointCount> drives;
  double pitch_limit;    ///< symmetric pitch range +-pitch_limit [rad], in [0, 70 deg]
  double yaw_limit;      ///< symmetric yaw range +-yaw_limit [rad], in [0, 70 deg]
  double insertion_max;  ///< insertion travel [0, insertion_max] [m], in (0, 0.30]
  double grip_max;       ///< jaw opening range [0, grip_max] [rad], in (0, 90 deg]

  TrocarDeviceConfig();
};

/// Drive data of one joint that a URDF cannot hold (see TrocarJointDrive for units and ranges).
struct TrocarMotor {
  double gear_ratio;     ///< [rad/rad] or [rad/m], > 0
  double rotor_inertia;  ///< [kg m^2], >= 0
  double encoder_step;   ///< [rad] or [m], > 0
};

/// Motors indexed by TrocarJoint (pitch, yaw, spin, insertion, grip).
using TrocarMotors = std::array<TrocarMotor, kTrocarJointCount>;

/// The prototype's motors (Chendeb 2007 §5.4.5), documented choices marked (ours):
/// - pitch/yaw: 0.01 deg encoder, direct drive (ratio 1), rotor 1e-5 kg m^2 (ours);
/// - spin: 0.05 deg encoder, gear ratio 10 (ours; not given in the thesis), rotor 1e-6 kg m^2;
/// - insertion: 0.1 mm encoder, friction rollers r = 5 mm (ratio 200 rad/m, ours), rotor
///   1e-6 kg m^2;
/// - grip (not built in the thesis; ours): 0.1 deg encoder, ratio 20, rotor 1e-7 kg m^2.
TrocarMotors chendebPrototypeMotors();

/// Throws std::invalid_argument naming the parameter, unit and range, e.g.
/// "trocar.pitch_limit = 80 deg is out of range: must be in [0 deg, 70 deg]" or
/// "trocar.spin.effort_limit = -1 N m is out of range: must be finite and > 0".
void validateTrocarDeviceConfig(const TrocarDeviceConfig& config);

}  // namespace surgical_sim::core
