#include "surgical_sim/core/haptics/haptic_loop.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>

#include "shipped_trocar.h"

namespace surgical_sim::core {
namespace {

HapticRendererConfig prototypeConfig() {
  HapticRendererConfig c;
  c.chain = shippedTrocar().chain;
  c.device = shippedDeviceConfig();
  c.coupling.stiffness = 3000.0;
  c.coupling.damping = 2.0;
  return c;
}

TEST(HapticRenderer, PushingIntoTissueAlongTheShaftRendersAnInsertionForceOnly) {
  HapticRenderer renderer(prototypeConfig());
  TrocarJointVector q = TrocarJointVector::Zero();
  q[kTrocarInsertion] = 0.1;  // tip at z = 0.12 m on the cannula axis
  // Tissue surface at z = 0.118 m, normal -z (toward the fulcrum), 400 N/m.
  LocalContactSample s;
  s.stamp = 0.0;
  s.p0_W = Eigen::Vector3d(0, 0, 0.12);
  s.f0_W = Eigen::Vector3d(0, 0, -400.0 * 0.002);
  s.K_W = Eigen::Vector3d(0, 0, -400.0).asDiagonal();
  renderer.setContactSample(s);
  HapticOutput out;
  for (int n = 0; n < 50; ++n) out = renderer.update(q, 1e-3 * n);
  EXPECT_EQ(out.contact_status, ContactStatus::Fresh);
  const double series = 3000.0 * 400.0 / 3400.0 * 0.002;  // coupling in series with tissue
  EXPECT_NEAR(out.effort[kTrocarInsertion], -series, 1e-6);
  EXPECT_NEAR(out.effort[kTrocarPitch], 0.0, 1e-12);
  EXPECT_NEAR(out.effort[kTrocarYaw], 0.0, 1e-12);
  EXPECT_NEAR(out.effort[kTrocarSpin], 0.0, 1e-12);
  EXPECT_FALSE(out.saturation.saturated);
}

TEST(HapticRenderer, InvalidConfigThrowsNamingTheParameter) {
  HapticRendererConfig c = prototypeConfig();
  c.rate_hz = 10.0;
  EXPECT_THROW(HapticRenderer{c}, std::invalid_argument);
  c = prototypeConfig();
  c.X_WF.linear() *= 2.0;
  EXPECT_THROW(HapticRenderer{c}, std::invalid_argument);
  c = prototypeConfig();
  c.coupling.stiffness = std::nan("");
  EXPECT_THROW(HapticRenderer{c}, std::invalid_argument);
  EXPECT_THROW(HapticLoop(prototypeConfig(), 4), std::invalid_argument);
}

TEST(HapticLoop, RunsTicksAndProducesFiniteOutputs) {
  HapticLoop loop(prototypeConfig(), 1024);
  TrocarJointVector q;
  q << 0.1, -0.2, 0.3, 0.12, 0.2;
  loop.setJointCommand(q);
  loop.start();
  LocalContactSample s;
  s.stamp = loop.now();
  s.p0_W = Eigen::Vector3d(0.0, 0.0, 0.1);
  s.f0_W = Eigen::Vector3d(0.2, -0.5, -1.0);
  s.K_W = -300.0 * Eigen::Matrix3d::Identity();
  loop.setContactModel(s);
  for (int i = 0; i < 30; ++i) {
    q[kTrocarInsertion] = 0.12 + 0.01 * std::sin(0.3 * i);
    loop.setJointCommand(q);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  loop.stop();
  EXPECT_FALSE(loop.running());
  const LoopStatistics stats = loop.statistics();
  const HapticOutput out = loop.latestOutput();
  EXPECT_GT(stats.ticks, 10u);
  EXPECT_GT(stats.samples, 0u);
  EXPECT_TRUE(std::isfinite(stats.period_mean));
  EXPECT_TRUE(std::isfinite(stats.period_p99));
  EXPECT_GE(stats.period_max, stats.period_p99);
  EXPECT_GT(out.tick, 0u);
  EXPECT_TRUE(out.effort.allFinite());
  EXPECT_TRUE(out.f_rendered_W.allFinite());
  EXPECT_TRUE(out.X_WT.matrix().allFinite());
  EXPECT_NE(out.contact_status, ContactStatus::NoModel);
  EXPECT_GT(out.effort.norm(), 0.0);
}

TEST(HapticLoop, PitchYawLimitsChangeWhileRunningAndInvalidOnesAreRejected) {
  const double deg = M_PI / 180.0;
  HapticLoop loop(prototypeConfig(), 64);
  EXPECT_THROW(loop.setPitchYawLimits(80.0 * deg, 10.0 * deg), std::invalid_argument);
  EXPECT_THROW(loop.setPitchYawLimits(10.0 * deg, std::nan("")), std::invalid_argument);
  double pitch = 0.0, yaw = 0.0;
  loop.pitchYawLimits(pitch, yaw);
  EXPECT_DOUBLE_EQ(pitch, 45.0 * deg);  // unchanged by the rejected requests
  EXPECT_DOUBLE_EQ(yaw, 45.0 * deg);

  TrocarJointVector q = TrocarJointVector::Zero();
  q[kTrocarPitch] = 0.5;  // 28.6 deg: inside +-45 deg, outside +-20 deg
  q[kTrocarYaw] = -0.5;
  loop.setJointCommand(q);
  loop.setPitchYawLimits(20.0 * deg, 20.0 * deg);
  loop.requestReset();
  loop.start();
  const std::uint64_t first_ticks = 20;
  while (loop.statistics().ticks < first_ticks)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  loop.stop();
  const HapticOutput out = loop.latestOutput();
  EXPECT_TRUE(out.joints_clamped);
  // Encoder reading of the clamped command: within half an encoder step (0.01 deg) of the limit.
  EXPECT_NEAR(out.q_measured[kTrocarPitch], 20.0 * deg, 0.005 * deg + 1e-12);
  EXPECT_NEAR(out.q_measured[kTrocarYaw], -20.0 * deg, 0.005 * deg + 1e-12);
  loop.pitchYawLimits(pitch, yaw);
  EXPECT_DOUBLE_EQ(pitch, 20.0 * deg);
}

}  // namespace
}  // namespace surgical_sim::core
