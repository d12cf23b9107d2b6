#include "surgical_sim/core/haptics/passivity_controller.h"

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace surgical_sim::core {
namespace {

TEST(PassivityController, PassiveDampedEnvironmentIsLeftUnchanged) {
  // A pure damper f = -b v is passive: E_obs never goes negative and no damping is added.
  PassivityController pc(PassivityControllerSettings{});
  for (int n = 0; n < 1000; ++n) {
    const Eigen::Vector3d v(std::sin(0.01 * n), 0.2, 0.0);
    const Eigen::Vector3d f = -3.0 * v;
    EXPECT_TRUE(pc.step(f, v, 1e-3).isApprox(f, 1e-15));
    EXPECT_EQ(pc.damping(), 0.0);
  }
  EXPECT_GE(pc.observedEnergy(), 0.0);
}

TEST(PassivityController, ActiveEnvironmentGetsExactlyTheDampingThatCancelsTheDeficit) {
  PassivityController pc(PassivityControllerSettings{});
  const Eigen::Vector3d v(0.1, 0.0, 0.0);
  pc.step(Eigen::Vector3d(0.5, 0.0, 0.0), v, 1e-3);  // held force pushes along v: active
  const Eigen::Vector3d out = pc.step(Eigen::Vector3d(0.5, 0.0, 0.0), v, 1e-3);
  // E_obs = -0.5 * 0.1 * 1e-3 = -5e-5 J -> alpha = 5e-5 / (0.01 * 1e-3) = 5 N s/m.
  EXPECT_NEAR(pc.observedEnergy(), -5e-5, 1e-15);
  EXPECT_NEAR(pc.damping(), 5.0, 1e-9);
  EXPECT_NEAR(out.x(), 0.5 - 5.0 * 0.1, 1e-12);
  EXPECT_NEAR(pc.dissipatedEnergy(), 5e-5, 1e-15);
}

TEST(PassivityController, InvalidSettingsThrowNamingTheParameter) {
  PassivityControllerSettings s;
  s.max_damping = 0.0;
  try {
    PassivityController pc(s);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "haptics.passivity.max_damping = 0 N s/m is out of range: must be finite and > 0");
  }
  s = PassivityControllerSettings{};
  s.min_speed = -1.0;
  EXPECT_THROW(PassivityController{s}, std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
