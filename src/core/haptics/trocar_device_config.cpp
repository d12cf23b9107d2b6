#include "surgical_sim/core/haptics/trocar_device_config.h"

#include <cmath>
#include <limits>
#include <string>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDegToRad = M_PI / 180.0;
constexpr double kRadToDeg = 180.0 / M_PI;

}  // namespace

TrocarJointDrive::TrocarJointDrive()
    : gear_ratio(kNaN),
      rotor_inertia(kNaN),
      viscous_friction(kNaN),
      coulomb_friction(kNaN),
      effort_limit(kNaN),
      encoder_step(kNaN) {}

TrocarDeviceConfig::TrocarDeviceConfig()
    : pitch_limit(kNaN), yaw_limit(kNaN), insertion_max(kNaN), grip_max(kNaN) {}

TrocarMotors chendebPrototypeMotors() {
  TrocarMotors m;
  m[kTrocarPitch] = {1.0, 1e-5, 0.01 * kDegToRad};
  m[kTrocarYaw] = {1.0, 1e-5, 0.01 * kDegToRad};
  m[kTrocarSpin] = {10.0, 1e-6, 0.05 * kDegToRad};
  m[kTrocarInsertion] = {200.0, 1e-6, 1e-4};
  m[kTrocarGrip] = {20.0, 1e-7, 0.1 * kDegToRad};
  return m;
}

void validateTrocarDeviceConfig(const TrocarDeviceConfig& config) {
  for (int j = 0; j < kTrocarJointCount; ++j) {
    const TrocarJointDrive& d = config.drives[j];
    const std::string prefix = std::string("trocar.") + trocarJointName(j) + ".";
    const bool prismatic = j == kTrocarInsertion;
    requirePositive(prefix + "gear_ratio", d.gear_ratio, prismatic ? "rad/m" : "rad/rad");
    requireNonNegative(prefix + "rotor_inertia", d.rotor_inertia, "kg m^2");
    requireNonNegative(prefix + "viscous_friction", d.viscous_friction,
                       prismatic ? "N s/m" : "N m s/rad");
    requireNonNegative(prefix + "coulomb_friction", d.coulomb_friction, prismatic ? "N" : "N m");
    requirePositive(prefix + "effort_limit", d.effort_limit, prismatic ? "N" : "N m");
    requirePositive(prefix + "encoder_step", d.encoder_step, prismatic ? "m" : "rad");
  }
  requireInRange("trocar.pitch_limit", config.pitch_limit * kRadToDeg, 0.0, kTrocarMaxTiltLimitDeg,
                 "deg");
  requireInRange("trocar.yaw_limit", config.yaw_limit * kRadToDeg, 0.0, kTrocarMaxTiltLimitDeg,
                 "deg");
  requirePositive("trocar.insertion_max", config.insertion_max, "m");
  requireInRange("trocar.insertion_max", config.insertion_max, 0.0, kTrocarMaxInsertion, "m");
  requirePositive("trocar.grip_max", config.grip_max, "rad");
  requireInRange("trocar.grip_max", config.grip_max * kRadToDeg, 0.0, kTrocarMaxGripDeg, "deg");
}

}  // namespace surgical_sim::core
