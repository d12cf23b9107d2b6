#include "surgical_sim/core/haptics/trocar_kinematics.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "shipped_trocar.h"

#include "surgical_sim/core/haptics/trocar_device.h"

namespace surgical_sim::core {
namespace {

constexpr double kDeg = M_PI / 180.0;

TrocarJointVector randomConfiguration(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(-70.0 * kDeg, 70.0 * kDeg);
  std::uniform_real_distribution<double> spin(-M_PI, M_PI);
  std::uniform_real_distribution<double> insertion(0.0, 0.30);
  std::uniform_real_distribution<double> grip(0.0, 1.0);
  TrocarJointVector q;
  q << angle(rng), angle(rng), spin(rng), insertion(rng), grip(rng);
  return q;
}

/// Tip velocity and angular velocity from central differences of the FK (Richardson-extrapolated,
/// O(h^4)), for joint velocity qdot.
SpatialVector finiteDifferenceTwist(const TrocarKinematics& kin, const TrocarJointVector& q,
                                    const TrocarJointVector& qdot, double h) {
  auto central = [&](double step) {
    const Eigen::Isometry3d plus = kin.toolTipPose(q + step * qdot);
    const Eigen::Isometry3d minus = kin.toolTipPose(q - step * qdot);
    SpatialVector twist;
    twist.head<3>() = (plus.translation() - minus.translation()) / (2.0 * step);
    const Eigen::AngleAxisd delta(plus.linear() * minus.linear().transpose());
    twist.tail<3>() = delta.angle() * delta.axis() / (2.0 * step);
    return twist;
  };
  return (4.0 * central(0.5 * h) - central(h)) / 3.0;
}

TEST(TrocarKinematics, HomeConfigurationPutsTipOnTheCannulaAxis) {
  const TrocarKinematics kin(shippedTrocar().chain);
  TrocarJointVector q = TrocarJointVector::Zero();
  q[kTrocarInsertion] = 0.1;
  const Eigen::Isometry3d X_FT = kin.toolTipPose(q);
  EXPECT_TRUE(X_FT.translation().isApprox(Eigen::Vector3d(0, 0, 0.12), 1e-15));
  EXPECT_TRUE(X_FT.linear().isIdentity(1e-15));
  // Pitch +90 deg about x turns the shaft from +z to -y.
  q[kTrocarPitch] = M_PI / 2;
  EXPECT_NEAR((kin.shaftAxis(q) - Eigen::Vector3d(0, -1, 0)).norm(), 0.0, 1e-15);
}

TEST(TrocarKinematics, JacobianMatchesFiniteDifferencesOfForwardKinematics) {
  const TrocarKinematics kin(shippedTrocar().chain);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 100; ++trial) {
    const TrocarJointVector q = randomConfiguration(rng);
    const TrocarJacobian J = kin.jacobian(q);
    for (int j = 0; j < kTrocarJointCount; ++j) {
      const TrocarJointVector unit = TrocarJointVector::Unit(j);
      const SpatialVector fd = finiteDifferenceTwist(kin, q, unit, 1e-4);
      EXPECT_LT((J.col(j) - fd).cwiseAbs().maxCoeff(), 1e-7) << "joint " << trocarJointName(j);
    }
    EXPECT_TRUE(J.col(kTrocarGrip).isZero(0.0));
  }
}

TEST(TrocarKinematics, VirtualWorkOfJointEffortsEqualsWorkOfTipWrench) {
  // tau . dq = f . dx + m . dtheta, with (dx, dtheta) from the forward kinematics.
  const TrocarKinematics kin(shippedTrocar().chain);
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const TrocarJointVector q = randomConfiguration(rng);
    SpatialVector w;
    TrocarJointVector qdot;
    for (int i = 0; i < 6; ++i) w[i] = 3.0 * normal(rng);
    for (int i = 0; i < kTrocarJointCount; ++i) qdot[i] = normal(rng);
    const TrocarJointVector tau = TrocarDevice::jointEfforts(kin.jacobian(q), w);
    const double joint_power = tau.dot(qdot);
    const double cartesian_power = w.dot(finiteDifferenceTwist(kin, q, qdot, 1e-3));
    EXPECT_NEAR(joint_power, cartesian_power, 1e-9) << "trial " << trial;
  }
}

TEST(TrocarKinematics, ShaftAlwaysPassesThroughTheFulcrum) {
  const TrocarKinematics kin(shippedTrocar().chain);
  std::mt19937 rng(3);
  double worst = 0.0;
  for (int trial = 0; trial < 1000; ++trial) {
    const TrocarJointVector q = randomConfiguration(rng);
    worst = std::max(worst, kin.fulcrumDistance(q));
    // The tip z axis is the shaft axis.
    EXPECT_LT((kin.toolTipPose(q).linear().col(2) - kin.shaftAxis(q)).norm(), 1e-14);
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(TrocarKinematics, ForceOnTheShaftLineProducesNoSpinTorque) {
  // A point force F at M = s e (on the shaft line through the fulcrum) has moment OM x F about
  // the fulcrum, which is perpendicular to e: no spin torque. Chendeb's eq. 5.4,
  // C_r = (X F_Y - Y F_X) / cos(theta), is not zero there.
  const TrocarKinematics kin(shippedTrocar().chain);
  TrocarJointVector q;
  q << 20.0 * kDeg, -30.0 * kDeg, 0.4, 0.12, 0.0;
  const Eigen::Vector3d e = kin.shaftAxis(q);
  const Eigen::Vector3d p_FT = kin.toolTipPose(q).translation();
  const Eigen::Vector3d F(1.5, -2.0, 0.7);
  for (const double s : {0.03, 0.08, 0.14}) {
    const Eigen::Vector3d p_FM = s * e;
    SpatialVector w;  // the point force moved to the tool tip
    w.head<3>() = F;
    w.tail<3>() = (p_FM - p_FT).cross(F);
    const TrocarJointVector tau = TrocarDevice::jointEfforts(kin.jacobian(q), w);
    EXPECT_NEAR(tau[kTrocarSpin], 0.0, 1e-12);
    // Pitch and yaw efforts are the projections of the moment about the fulcrum.
    const Eigen::Vector3d moment_O = p_FM.cross(F);
    const double cp = std::cos(q[kTrocarPitch]), sp = std::sin(q[kTrocarPitch]);
    EXPECT_NEAR(tau[kTrocarPitch], moment_O.x(), 1e-12);
    EXPECT_NEAR(tau[kTrocarYaw], moment_O.dot(Eigen::Vector3d(0, cp, sp)), 1e-12);
    EXPECT_NEAR(tau[kTrocarInsertion], F.dot(e), 1e-12);
    const double cos_theta = e.z();
    const double thesis_spin = (p_FM.x() * F.y() - p_FM.y() * F.x()) / cos_theta;
    EXPECT_GT(std::abs(thesis_spin), 1e-2) << "s = " << s;
  }
}

TEST(TrocarKinematics, InvalidChainThrowsNamingTheParameter) {
  TrocarChain chain = shippedTrocar().chain;
  chain.joints[kTrocarYaw].axis = Eigen::Vector3d(0.0, 2.0, 0.0);
  try {
    TrocarKinematics kin(chain);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("trocar.chain.yaw.axis"), std::string::npos) << e.what();
  }
  EXPECT_THROW(TrocarKinematics{TrocarChain()}, std::invalid_argument);
  chain = shippedTrocar().chain;
  chain.joints[kTrocarInsertion].type = TrocarJointType::Revolute;
  EXPECT_THROW(TrocarKinematics{chain}, std::invalid_argument);
  chain = shippedTrocar().chain;
  chain.X_JT.linear() *= 2.0;
  EXPECT_THROW(TrocarKinematics{chain}, std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
