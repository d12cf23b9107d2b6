// The scene URDF: four trocars (and a robot) under `world`; each trocar read back from it is the
// shipped model placed at its fulcrum, and its FK equals the URDF chain from world.
#include "surgical_sim/core/scene/scene_urdf.h"

#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "../common/urdf_link_pose.h"
#include "surgical_sim/core/common/text_file.h"
#include "surgical_sim/core/haptics/trocar_kinematics.h"
#include "surgical_sim/core/haptics/trocar_urdf.h"
#include "surgical_sim/core/robot/continuum_robot_loader.h"

namespace surgical_sim::core {
namespace {

std::string trocarText() {
  return readTextFile(std::string(SURGICAL_SIM_SOURCE_DIR) + "/urdf/active_trocar.urdf");
}

std::vector<ContinuumRobotDescription> shippedRobots() {
  const std::string config = std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/continuum_robot.yaml";
  return {loadContinuumRobot(config, "trunk"), loadContinuumRobot(config, "cable")};
}

Eigen::Isometry3d pose(double x, double y, double z, double roll, double pitch, double yaw) {
  return Eigen::Translation3d(x, y, z) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

std::vector<TrocarPlacement> fourTrocars() {
  return {{"trocar_0", pose(-0.05, 0.0, 0.2, M_PI, 0.0, 0.0)},
          {"trocar_1", pose(0.05, 0.0, 0.2, M_PI, 0.3, 0.0)},
          {"left", pose(0.0, -0.06, 0.18, 2.8, -0.2, 1.0)},
          {"Right_2", pose(0.0, 0.06, 0.18, -2.8, 0.1, -2.5)}};
}

TEST(SceneUrdf, EachOfFourTrocarsIsTheShippedModelAtItsFulcrum) {
  const std::vector<TrocarPlacement> trocars = fourTrocars();
  const std::string text = sceneUrdf(trocars, std::nullopt, trocarText(), {});
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->getRoot()->name, "world");
  const TrocarUrdf shipped = readTrocarUrdf(trocarText(), TrocarUrdfNames::forTrocar("trocar"));
  const TrocarKinematics reference(shipped.chain);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const TrocarPlacement& placement : trocars) {
    const std::string& T = placement.name;
    for (const char* link : {"", "_cradle", "_instrument_shaft", "_jaw_upper", "_tool_tip"})
      EXPECT_TRUE(model->getLink(T + link)) << T + link;
    EXPECT_EQ(model->getJoint("world_to_" + T)->parent_link_name, "world");
    const TrocarUrdf trocar = readTrocarUrdf(text, TrocarUrdfNames::forTrocar(T));
    ASSERT_TRUE(trocar.X_WF.has_value());
    EXPECT_LT((trocar.X_WF->matrix() - placement.X_WF.matrix()).cwiseAbs().maxCoeff(), 1e-12) << T;
    for (int j = 0; j < kTrocarJointCount; ++j)
      EXPECT_EQ(trocar.joints[j].upper, shipped.joints[j].upper) << T;
    const TrocarKinematics kin(trocar.chain);
    for (int trial = 0; trial < 50; ++trial) {
      TrocarJointVector q;
      q << 0.78 * u(rng), 0.78 * u(rng), M_PI * u(rng), 0.15 * (1.0 + u(rng)), 0.5 * (1.0 + u(rng));
      std::map<std::string, double> positions;
      for (int j = 0; j < kTrocarJointCount; ++j) positions[T + "_" + trocarJointName(j)] = q[j];
      const Eigen::Isometry3d X_WT =
          test::urdfLinkPose(*model, "world", T + "_tool_tip", positions);
      const Eigen::Isometry3d expected = placement.X_WF * reference.toolTipPose(q);
      EXPECT_LT((X_WT.matrix() - expected.matrix()).cwiseAbs().maxCoeff(), 1e-12) << T;
      EXPECT_LT(
          (X_WT.matrix() - (*trocar.X_WF * kin.toolTipPose(q)).matrix()).cwiseAbs().maxCoeff(),
          1e-12)
          << T;
    }
  }
}

TEST(SceneUrdf, RobotHangsFromWorldAtItsBasePose) {
  const Eigen::Isometry3d X_WB = pose(0.3, 0.0, 0.1, 0.0, 0.0, 0.7);
  const std::string text =
      sceneUrdf({fourTrocars()[0]}, RobotPlacement{"cable", X_WB}, trocarText(), shippedRobots());
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text);
  ASSERT_TRUE(model);
  EXPECT_TRUE(model->getLink("vertebra_10"));
  EXPECT_FALSE(model->getLink("vertebra_11"));  // the cable robot, not the trunk
  EXPECT_TRUE(model->getLink("trocar_0_tool_tip"));
  const Eigen::Isometry3d X = test::urdfLinkPose(*model, "world", "robot_base", {});
  EXPECT_LT((X.matrix() - X_WB.matrix()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(model->getJoint("world_to_robot_base")->type, urdf::Joint::FIXED);
}

TEST(SceneUrdf, BadInputsGiveErrorsNamingTheProblem) {
  const auto errorOf = [](const std::vector<TrocarPlacement>& trocars,
                          const std::optional<RobotPlacement>& robot, const std::string& urdf) {
    try {
      sceneUrdf(trocars, robot, urdf, shippedRobots());
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const TrocarPlacement t = fourTrocars()[0];
  EXPECT_NE(errorOf({t, t}, std::nullopt, trocarText()).find("'trocar_0' appears twice"),
            std::string::npos);
  EXPECT_NE(errorOf({{"0bad", t.X_WF}}, std::nullopt, trocarText()).find("'0bad' is invalid"),
            std::string::npos);
  TrocarPlacement skewed = t;
  skewed.X_WF.linear() *= 2.0;
  EXPECT_NE(errorOf({skewed}, std::nullopt, trocarText()).find("pose of trocar 'trocar_0'"),
            std::string::npos);
  EXPECT_NE(errorOf({t}, std::nullopt, "<link/>").find("not a URDF <robot> document"),
            std::string::npos);
  EXPECT_NE(errorOf({}, RobotPlacement{"snake", Eigen::Isometry3d::Identity()}, "")
                .find("'snake' is unknown (known: trunk, cable)"),
            std::string::npos);
  EXPECT_NE(errorOf({{"vertebra_1", t.X_WF}},
                    RobotPlacement{"cable", Eigen::Isometry3d::Identity()}, trocarText())
                .find("urdfdom rejects"),
            std::string::npos);
}

}  // namespace
}  // namespace surgical_sim::core
