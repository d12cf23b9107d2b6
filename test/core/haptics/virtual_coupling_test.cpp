#include "surgical_sim/core/haptics/virtual_coupling.h"

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace surgical_sim::core {
namespace {

VirtualCouplingSettings gains(double k, double b) {
  VirtualCouplingSettings s;
  s.stiffness = k;
  s.damping = b;
  return s;
}

TEST(VirtualCoupling, StaticContactRendersTheSeriesStiffness) {
  // Wall z < 0 with stiffness K_e = 5000 N/m, coupling k = 2000 N/m: a device tip held 1 mm inside
  // feels (k K_e / (k + K_e)) * 1 mm once the proxy has settled.
  const double k = 2000.0, K_e = 5000.0, dt = 1e-3;
  VirtualCoupling coupling(gains(k, 5.0));
  const Eigen::Vector3d p_device(0.0, 0.0, -0.001);
  coupling.reset(p_device);
  const Eigen::Matrix3d K = Eigen::Vector3d(0.0, 0.0, -K_e).asDiagonal();
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p_P = coupling.proxyPosition();
    // The wall's exact linearization at the proxy (penetration -z).
    const Eigen::Vector3d f_c(0.0, 0.0, -K_e * std::min(0.0, p_P.z()));
    f = coupling.step(p_device, Eigen::Vector3d::Zero(), f_c, K, p_P, dt);
  }
  const double series = k * K_e / (k + K_e);
  EXPECT_NEAR(f.z(), series * 0.001, 1e-9);
  EXPECT_NEAR(f.x(), 0.0, 1e-15);
  // The proxy sits where the coupling and the wall forces balance.
  EXPECT_NEAR(coupling.proxyPosition().z(), -0.001 * k / (k + K_e), 1e-12);
}

TEST(VirtualCoupling, FreeSpaceDamperOpposesMotion) {
  VirtualCoupling coupling(gains(1000.0, 2.0));
  coupling.reset(Eigen::Vector3d::Zero());
  const Eigen::Vector3d f = coupling.step(Eigen::Vector3d(0.001, 0.0, 0.0),
                                          Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d::Zero(),
                                          Eigen::Matrix3d::Zero(), Eigen::Vector3d::Zero(), 1e-3);
  // Without environment the massless proxy follows the tip: no force.
  EXPECT_LT(f.norm(), 1e-12);
  EXPECT_TRUE(coupling.proxyPosition().isApprox(Eigen::Vector3d(0.001, 0.0, 0.0), 1e-12));
}

TEST(VirtualCoupling, NonFiniteInputsGiveZeroForce) {
  VirtualCoupling coupling(gains(1000.0, 2.0));
  const Eigen::Vector3d f = coupling.step(Eigen::Vector3d(std::nan(""), 0, 0),
                                          Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                          Eigen::Matrix3d::Zero(), Eigen::Vector3d::Zero(), 1e-3);
  EXPECT_TRUE(f.isZero(0.0));
  EXPECT_TRUE(coupling.proxyPosition().allFinite());
}

TEST(VirtualCoupling, InvalidGainsThrowNamingTheParameter) {
  try {
    VirtualCoupling coupling(gains(-1.0, 1.0));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "haptics.coupling.stiffness = -1 N/m is out of range: must be finite and > 0");
  }
  EXPECT_THROW(VirtualCoupling{gains(1000.0, -0.1)}, std::invalid_argument);
  EXPECT_THROW(VirtualCoupling{VirtualCouplingSettings{}}, std::invalid_argument);  // no defaults
}

}  // namespace
}  // namespace surgical_sim::core
