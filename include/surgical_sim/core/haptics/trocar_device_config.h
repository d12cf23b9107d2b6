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

/// Configuration of the active trocar device model (Chendeb 2007 §5.3–5.4).
struct TrocarDeviceConfig {
  /// Drives indexed by TrocarJoint (pitch, yaw, spin, insertion, grip).
  std::array<TrocarJointDrive, kTrocarJointCount> drives;
  double pitch_limit;    ///< symmetric pitch range +-pitch_limit [rad], in [0, 70 deg]
  double yaw_limit;      ///< symmetric yaw range +-yaw_limit [rad], in [0, 70 deg]
  double insertion_max;  ///< insertion travel [0, insertion_max] [m], in (0, 0.30]
  double grip_max;       ///< jaw opening range [0, grip_max] [rad], in (0, 90 deg]

  TrocarDeviceConfig();

  /// The prototype as built (Chendeb 2007 §5.4.5), documented choices marked (ours):
  /// - pitch/yaw: +-45 deg, 0.01 deg encoder, 6 N m, direct drive (ratio 1), rotor 1e-5 kg m^2
  ///   (ours), viscous 0.005 N m s/rad (ours), Coulomb 0.01 N m (ours);
  /// - spin: continuous, 0.05 deg encoder, 0.2 N m, gear ratio 10 (ours; value not given in the
  ///   thesis), rotor 1e-6 kg m^2, viscous 5e-4 N m s/rad, Coulomb 2e-3 N m (ours);
  /// - insertion: 0.30 m, 0.1 mm encoder, 5 N, friction rollers r = 5 mm (ratio 200 rad/m, ours),
  ///   rotor 1e-6 kg m^2, viscous 0.2 N s/m, Coulomb 0.1 N (ours);
  /// - grip (not built in the thesis; ours): 0..60 deg, 0.1 deg encoder, 0.3 N m jaw torque,
  ///   ratio 20, rotor 1e-7 kg m^2, viscous 1e-4 N m s/rad, Coulomb 1e-3 N m.
  static TrocarDeviceConfig chendebPrototype();
};

/// Throws std::invalid_argument naming the parameter, unit and range, e.g.
/// "trocar.pitch_limit = 80 deg is out of range: must be in [0 deg, 70 deg]" or
/// "trocar.spin.effort_limit = -1 N m is out of range: must be finite and > 0".
void validateTrocarDeviceConfig(const TrocarDeviceConfig& config);

}  // namespace surgical_sim::core
