#include "surgical_sim/core/haptics/trocar_device.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "shipped_trocar.h"

namespace surgical_sim::core {
namespace {

constexpr double kDeg = M_PI / 180.0;

std::string errorOf(const TrocarDeviceConfig& config) {
  try {
    TrocarDevice device(config);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(TrocarDevice, JointLimitsClampAndSpinWraps) {
  const TrocarDevice device(shippedDeviceConfig());
  TrocarJointVector q;
  q << 50.0 * kDeg, -60.0 * kDeg, 3.0 * M_PI, 0.35, -0.1;
  EXPECT_TRUE(device.clampToLimits(q));
  EXPECT_DOUBLE_EQ(q[kTrocarPitch], 45.0 * kDeg);
  EXPECT_DOUBLE_EQ(q[kTrocarYaw], -45.0 * kDeg);
  EXPECT_NEAR(q[kTrocarSpin], -M_PI, 1e-12);  // 3 pi wraps to -pi
  EXPECT_DOUBLE_EQ(q[kTrocarInsertion], 0.30);
  EXPECT_DOUBLE_EQ(q[kTrocarGrip], 0.0);

  TrocarJointVector inside;
  inside << 10.0 * kDeg, -10.0 * kDeg, 7.0, 0.1, 0.2;
  EXPECT_FALSE(device.clampToLimits(inside));  // wrapping the spin is not clamping
  EXPECT_NEAR(inside[kTrocarSpin], 7.0 - 2.0 * M_PI, 1e-12);

  TrocarJointVector bad = TrocarJointVector::Constant(std::nan(""));
  EXPECT_TRUE(device.clampToLimits(bad));
  EXPECT_TRUE(bad.allFinite());
}

TEST(TrocarDevice, LimitsCanBeWidenedToSeventyDegreesButNotBeyond) {
  TrocarDevice device(shippedDeviceConfig());
  device.setPitchYawLimits(70.0 * kDeg, 60.0 * kDeg);
  TrocarJointVector q;
  q << 69.0 * kDeg, 65.0 * kDeg, 0.0, 0.1, 0.0;
  device.clampToLimits(q);
  EXPECT_DOUBLE_EQ(q[kTrocarPitch], 69.0 * kDeg);
  EXPECT_DOUBLE_EQ(q[kTrocarYaw], 60.0 * kDeg);
  try {
    device.setPitchYawLimits(80.0 * kDeg, 45.0 * kDeg);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "trocar.pitch_limit = 80 deg is out of range: must be in [0 deg, 70 deg]");
  }
  EXPECT_DOUBLE_EQ(device.config().pitch_limit, 70.0 * kDeg);  // unchanged after the failure
}

TEST(TrocarDevice, EncoderQuantizationUsesTheDocumentedSteps) {
  const TrocarDevice device(shippedDeviceConfig());
  const double steps[kTrocarJointCount] = {0.01 * kDeg, 0.01 * kDeg, 0.05 * kDeg, 1e-4, 0.1 * kDeg};
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 500; ++trial) {
    TrocarJointVector q;
    q << (u(rng) - 0.5) * 80.0 * kDeg, (u(rng) - 0.5) * 80.0 * kDeg, (u(rng) - 0.5) * 6.0,
        0.3 * u(rng), 1.0 * u(rng);
    const TrocarJointVector reading = device.quantize(q);
    for (int j = 0; j < kTrocarJointCount; ++j) {
      const double counts = reading[j] / steps[j];
      EXPECT_NEAR(counts, std::round(counts), 1e-6) << trocarJointName(j);
      EXPECT_LE(std::abs(reading[j] - q[j]), 0.5 * steps[j] * (1.0 + 1e-9)) << trocarJointName(j);
    }
  }
  // A motion smaller than half a step is invisible, one step is seen as exactly one step.
  TrocarJointVector q = TrocarJointVector::Zero();
  q[kTrocarInsertion] = 0.1;
  const double base = device.quantize(q)[kTrocarInsertion];
  q[kTrocarInsertion] += 0.4e-4;
  EXPECT_DOUBLE_EQ(device.quantize(q)[kTrocarInsertion], base);
  q[kTrocarInsertion] = 0.1 + 1e-4;
  EXPECT_NEAR(device.quantize(q)[kTrocarInsertion] - base, 1e-4, 1e-12);
}

TEST(TrocarDevice, SaturationPreservesTheEffortDirection) {
  const TrocarDevice device(shippedDeviceConfig());
  TrocarJointVector tau;
  tau << 3.0, -12.0, 0.1, 8.0, 0.0;  // yaw 2x over its 6 N m, insertion 1.6x over its 5 N
  const TrocarJointVector original = tau;
  const EffortSaturation s = device.saturate(tau);
  EXPECT_TRUE(s.saturated);
  EXPECT_DOUBLE_EQ(s.scale, 0.5);
  EXPECT_TRUE(tau.isApprox(0.5 * original, 1e-15));
  EXPECT_NEAR(tau.normalized().dot(original.normalized()), 1.0, 1e-15);
  for (int j = 0; j < kTrocarJointCount; ++j)
    EXPECT_LE(std::abs(tau[j]), device.config().drives[j].effort_limit + 1e-12);

  TrocarJointVector small;
  small << 1.0, 1.0, 0.1, 1.0, 0.1;
  const EffortSaturation none = device.saturate(small);
  EXPECT_FALSE(none.saturated);
  EXPECT_EQ(none.scale, 1.0);

  TrocarJointVector bad = small;
  bad[2] = std::nan("");
  const EffortSaturation nan = device.saturate(bad);
  EXPECT_TRUE(nan.non_finite);
  EXPECT_TRUE(bad.isZero(0.0));
}

TEST(TrocarDevice, MotorTorqueFrictionAndReflectedInertiaFollowTheTransmission) {
  const TrocarDevice device(shippedDeviceConfig());
  TrocarJointVector tau;
  tau << 6.0, 6.0, 0.2, 5.0, 0.3;
  const TrocarJointVector motor = device.motorTorques(tau);
  EXPECT_DOUBLE_EQ(motor[kTrocarSpin], 0.02);        // ratio 10
  EXPECT_DOUBLE_EQ(motor[kTrocarInsertion], 0.025);  // 5 N on a 5 mm roller
  TrocarJointVector qdot;
  qdot << 1.0, -1.0, 0.0, 0.1, 0.0;
  const TrocarJointVector friction = device.frictionEfforts(qdot);
  EXPECT_DOUBLE_EQ(friction[kTrocarPitch], -(0.005 + 0.01));
  EXPECT_DOUBLE_EQ(friction[kTrocarYaw], 0.005 + 0.01);
  EXPECT_DOUBLE_EQ(friction[kTrocarSpin], 0.0);
  EXPECT_LE(friction.dot(qdot), 0.0);  // dissipative
  EXPECT_NEAR(device.reflectedInertia()[kTrocarInsertion], 1e-6 * 200.0 * 200.0, 1e-15);
}

TEST(TrocarDevice, InvalidConfigurationsThrowNamingParameterUnitAndRange) {
  TrocarDeviceConfig c = shippedDeviceConfig();
  c.yaw_limit = 75.0 * kDeg;
  EXPECT_EQ(errorOf(c), "trocar.yaw_limit = 75 deg is out of range: must be in [0 deg, 70 deg]");
  c = shippedDeviceConfig();
  c.drives[kTrocarSpin].effort_limit = -1.0;
  EXPECT_EQ(errorOf(c),
            "trocar.spin.effort_limit = -1 N m is out of range: must be finite and > 0");
  c = shippedDeviceConfig();
  c.insertion_max = 0.4;
  EXPECT_EQ(errorOf(c), "trocar.insertion_max = 0.4 m is out of range: must be in [0 m, 0.3 m]");
  c = shippedDeviceConfig();
  c.drives[kTrocarInsertion].encoder_step = 0.0;
  EXPECT_NE(errorOf(c).find("trocar.insertion.encoder_step = 0 m"), std::string::npos);
  c = shippedDeviceConfig();
  c.drives[kTrocarPitch].gear_ratio = 0.0;
  EXPECT_NE(errorOf(c).find("trocar.pitch.gear_ratio"), std::string::npos);
  c = shippedDeviceConfig();
  c.drives[kTrocarYaw].viscous_friction = -1.0;
  EXPECT_NE(errorOf(c).find("trocar.yaw.viscous_friction"), std::string::npos);
  c = shippedDeviceConfig();
  c.drives[kTrocarGrip].coulomb_friction = -1.0;
  EXPECT_NE(errorOf(c).find("trocar.grip.coulomb_friction"), std::string::npos);
  c = shippedDeviceConfig();
  c.drives[kTrocarGrip].rotor_inertia = std::nan("");
  EXPECT_NE(errorOf(c).find("trocar.grip.rotor_inertia"), std::string::npos);
  c = shippedDeviceConfig();
  c.grip_max = 2.0;
  EXPECT_NE(errorOf(c).find("trocar.grip_max"), std::string::npos);
  // No silent defaults: an unfilled configuration is rejected.
  EXPECT_FALSE(errorOf(TrocarDeviceConfig()).empty());
}

}  // namespace
}  // namespace surgical_sim::core
