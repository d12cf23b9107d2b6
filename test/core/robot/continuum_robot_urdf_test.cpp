// Generated continuum-robot URDFs: urdfdom parses them and their links are exactly the tf frames
// the controller publishes, at the model's rest poses.
#include "surgical_sim/core/robot/continuum_robot_urdf.h"

#include <urdf_parser/urdf_parser.h>

#include <set>
#include <string>

#include <gtest/gtest.h>

#include "robot_test_fixtures.h"
#include "surgical_sim/core/robot/continuum_robot_loader.h"
#include "surgical_sim/core/robot/continuum_robot_model.h"
#include "surgical_sim/core/robot/section_compliances.h"

namespace surgical_sim::core {
namespace {

/// Frames continuum_robot_controller publishes for a model with `nodes` rigid nodes (0 = base).
std::set<std::string> publishedFrames(const ContinuumRobotFrames& frames, std::size_t nodes) {
  std::set<std::string> names = {frames.base, frames.tip};
  for (std::size_t k = 1; k < nodes; ++k) names.insert(frames.rigidNode(static_cast<int>(k)));
  return names;
}

/// Parses the URDF of `d`, checks links = frames, joint tree and rest-pose origins.
void expectUrdfMatchesTheModel(const ContinuumRobotDescription& d,
                               const std::vector<RigidNodePose>& rest,
                               const ContinuumRobotFrames& frames) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(continuumRobotUrdf(d, frames));
  ASSERT_TRUE(model) << d.name;
  std::set<std::string> links;
  for (const auto& [name, link] : model->links_) links.insert(name);
  EXPECT_EQ(links, publishedFrames(frames, rest.size())) << d.name;
  EXPECT_EQ(model->getRoot()->name, frames.base);
  for (std::size_t k = 1; k < rest.size(); ++k) {
    const urdf::JointConstSharedPtr joint =
        model->getLink(frames.rigidNode(static_cast<int>(k)))->parent_joint;
    ASSERT_TRUE(joint);
    EXPECT_EQ(joint->type, urdf::Joint::FLOATING);
    EXPECT_EQ(joint->parent_link_name, frames.base);
    const urdf::Vector3& p = joint->parent_to_joint_origin_transform.position;
    EXPECT_LT((Eigen::Vector3d(p.x, p.y, p.z) - rest[k].p_BN).norm(), 1e-15) << "rigid node " << k;
    EXPECT_TRUE(rest[k].q_BN.toRotationMatrix().isIdentity(0.0));
  }
  const urdf::JointConstSharedPtr tip = model->getLink(frames.tip)->parent_joint;
  EXPECT_EQ(tip->type, urdf::Joint::FLOATING);
  EXPECT_EQ(tip->parent_link_name, frames.rigidNode(static_cast<int>(rest.size()) - 1));
}

TEST(ContinuumRobotUrdf, LinksAreTheFramesTheModelPublishesAtItsRestPoses) {
  const ContinuumRobotDescription d = test::smallCableRobot(5);
  const ContinuumRobotModel model(d, computeSectionCompliances(d, ""));
  expectUrdfMatchesTheModel(d, model.restNodes(), ContinuumRobotFrames());
  ContinuumRobotFrames renamed;
  renamed.base = "arm_base";
  renamed.link_prefix = "arm_node_";
  renamed.tip = "arm_tip";
  expectUrdfMatchesTheModel(d, model.restNodes(), renamed);
}

TEST(ContinuumRobotUrdf, ShippedTrunkAndCableRobotsHaveTheirOwnLinks) {
  const std::string config = std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/continuum_robot.yaml";
  for (const auto& [name, vertebrae] : {std::pair<std::string, int>{"trunk", 16}, {"cable", 10}}) {
    const ContinuumRobotDescription d = loadContinuumRobot(config, name);
    ASSERT_EQ(d.num_vertebrae, vertebrae);
    std::vector<RigidNodePose> rest(static_cast<std::size_t>(vertebrae) + 1);
    for (int k = 0; k <= vertebrae; ++k)
      rest[k].p_BN = Eigen::Vector3d(k * d.vertebra_spacing, 0, 0);
    expectUrdfMatchesTheModel(d, rest, ContinuumRobotFrames());
  }
}

TEST(ContinuumRobotUrdf, InvalidDescriptionThrows) {
  ContinuumRobotDescription d = test::smallCableRobot();
  d.vertebra_spacing = -1.0;
  EXPECT_THROW(continuumRobotUrdf(d), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
