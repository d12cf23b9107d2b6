#include <gtest/gtest.h>

#include "robot_test_fixtures.h"
#include "surgical_sim/core/robot/cable_actuator.h"
#include "surgical_sim/core/robot/pressure_chamber_actuator.h"
#include "surgical_sim/core/robot/so3.h"

namespace surgical_sim::core {
namespace {

std::vector<RigidNodePose> bentPoses(int n, double spacing) {
  std::vector<RigidNodePose> nodes(n + 1);
  for (int k = 1; k <= n; ++k) {
    nodes[k].q_BN = expRotation(Eigen::Vector3d(0.05, 0.1 * k, -0.07 * k));
    nodes[k].p_BN = nodes[k - 1].p_BN + nodes[k - 1].q_BN * Eigen::Vector3d(spacing, 0.001, 0.0);
  }
  return nodes;
}

// Both bounding nodes moved together as one rigid body: the closed chamber's pressure forces
// must cancel (zero net force and torque).
TEST(PressureChamberActuator, ClosedChamberGivesZeroNetWrenchOnARigidBody) {
  const ContinuumRobotDescription d = test::smallPressureRobot();
  const PressureChamberActuator chamber(d.chambers[0], d, 16, 3);
  const std::vector<RigidNodePose> nodes = bentPoses(d.num_vertebrae, d.vertebra_spacing);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(6 * (d.num_vertebrae + 1));
  chamber.addGradient(nodes, 1e5, g);
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  for (int k = 0; k <= d.num_vertebrae; ++k) {
    force += g.segment<3>(6 * k);
    torque += g.segment<3>(6 * k + 3) + nodes[k].p_BN.cross(Eigen::Vector3d(g.segment<3>(6 * k)));
  }
  const double scale = 1e5 * M_PI * 0.001 * 0.001;  // p A of one cap [N]
  EXPECT_LT(force.norm(), 1e-10 * scale);
  EXPECT_LT(torque.norm(), 1e-10 * scale * 0.1);
  // Each vertebra face alone does feel the pressure: p A along the axis (rest, first node).
  std::vector<RigidNodePose> rest(d.num_vertebrae + 1);
  for (int k = 0; k <= d.num_vertebrae; ++k) rest[k].p_BN.x() = k * d.vertebra_spacing;
  const PressureChamberActuator fine(d.chambers[0], d, 256, 1);
  g.setZero();
  fine.addGradient(rest, 1e5, g);
  EXPECT_NEAR(g[0], -scale, 1e-3 * scale);
  EXPECT_NEAR(g[6 * d.num_vertebrae], scale, 1e-3 * scale);
}

TEST(ChainActuators, GradientIsTheDerivativeOfTheMeasure) {
  const ContinuumRobotDescription pd = test::smallPressureRobot();
  const ContinuumRobotDescription cd = test::smallCableRobot();
  const PressureChamberActuator chamber(pd.chambers[1], pd, 12, 2);
  const CableActuator cable(cd.cables[1]);
  const std::vector<RigidNodePose> nodes = bentPoses(4, 0.02);
  for (const ChainActuator* a :
       {static_cast<const ChainActuator*>(&chamber), static_cast<const ChainActuator*>(&cable)}) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(30);
    a->addGradient(nodes, 1.0, g);
    const double h = 1e-7;
    for (int d = 0; d < 30; ++d) {
      std::vector<RigidNodePose> p = nodes, m = nodes;
      const int k = d / 6, c = d % 6;
      if (c < 3) {
        p[k].p_BN[c] += h;
        m[k].p_BN[c] -= h;
      } else {
        p[k].q_BN = expRotation(h * Eigen::Vector3d::Unit(c - 3)) * p[k].q_BN;
        m[k].q_BN = expRotation(-h * Eigen::Vector3d::Unit(c - 3)) * m[k].q_BN;
      }
      const double fd = (a->measure(p) - a->measure(m)) / (2 * h);
      EXPECT_NEAR(g[d], fd, 1e-6 * g.norm()) << a->name() << " dof " << d;
    }
  }
}

TEST(ChainActuators, RestChamberVolumeAndCableLength) {
  const ContinuumRobotDescription d = test::smallPressureRobot();
  const PressureChamberActuator chamber(d.chambers[0], d, 512, 1);
  std::vector<RigidNodePose> rest(5);
  for (int k = 0; k <= 4; ++k) rest[k].p_BN.x() = k * d.vertebra_spacing;
  const double ell = d.vertebra_spacing - d.vertebra_thickness;
  EXPECT_NEAR(chamber.measure(rest), 4 * M_PI * 1e-6 * ell, 1e-4 * 4 * M_PI * 1e-6 * ell);
  const CableActuator cable(test::smallCableRobot().cables[0]);
  EXPECT_NEAR(cable.measure(rest), -0.08, 1e-15);
  EXPECT_THROW(PressureChamberActuator(d.chambers[0], d, 2, 1), std::invalid_argument);
  EXPECT_THROW(PressureChamberActuator(d.chambers[0], d, 8, 0), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
