#include "surgical_sim/core/common/tool_pose_check.h"

#include <gtest/gtest.h>

#include <limits>

namespace surgical_sim::core {
namespace {

TEST(ToolPoseCheck, AcceptsFiniteNearPosesWithAUsableQuaternion) {
  const Eigen::Vector4d identity(1.0, 0.0, 0.0, 0.0);
  EXPECT_TRUE(isUsableToolPose(Eigen::Vector3d(0.1, -0.2, 0.3), identity, 5.0));
  EXPECT_TRUE(isUsableToolPose(Eigen::Vector3d(5.0, 0.0, 0.0), identity, 5.0));  // on the bound
  EXPECT_TRUE(isUsableToolPose(Eigen::Vector3d::Zero(), 0.5 * identity, 5.0));
  EXPECT_TRUE(isUsableToolPose(Eigen::Vector3d::Zero(), 2.0 * identity, 5.0));
}

TEST(ToolPoseCheck, RejectsNonFiniteZeroOrScaledQuaternionAndFarPoses) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const Eigen::Vector4d identity(1.0, 0.0, 0.0, 0.0);
  EXPECT_FALSE(isUsableToolPose(Eigen::Vector3d(nan, 0.0, 0.0), identity, 5.0));
  EXPECT_FALSE(isUsableToolPose(Eigen::Vector3d(0.0, -inf, 0.0), identity, 5.0));
  EXPECT_FALSE(isUsableToolPose(Eigen::Vector3d::Zero(), Eigen::Vector4d(1.0, nan, 0.0, 0.0), 5.0));
  EXPECT_FALSE(isUsableToolPose(Eigen::Vector3d::Zero(), Eigen::Vector4d::Zero(), 5.0));
  EXPECT_FALSE(isUsableToolPose(Eigen::Vector3d::Zero(), 0.49 * identity, 5.0));
  EXPECT_FALSE(isUsableToolPose(Eigen::Vector3d::Zero(), 2.01 * identity, 5.0));
  EXPECT_FALSE(isUsableToolPose(Eigen::Vector3d(0.0, 0.0, 5.001), identity, 5.0));
}

TEST(ToolPoseCheck, NamesEachKindOfProblem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector4d identity(1.0, 0.0, 0.0, 0.0);
  EXPECT_EQ(toolPoseProblem(Eigen::Vector3d::Zero(), identity, 5.0), ToolPoseProblem::None);
  EXPECT_EQ(toolPoseProblem(Eigen::Vector3d(nan, 0.0, 0.0), identity, 5.0),
            ToolPoseProblem::NonFinitePosition);
  EXPECT_EQ(toolPoseProblem(Eigen::Vector3d::Zero(), Eigen::Vector4d::Zero(), 5.0),
            ToolPoseProblem::BadQuaternion);
  EXPECT_EQ(toolPoseProblem(Eigen::Vector3d::Zero(), Eigen::Vector4d(1.0, nan, 0.0, 0.0), 5.0),
            ToolPoseProblem::BadQuaternion);
  EXPECT_EQ(toolPoseProblem(Eigen::Vector3d(0.0, 0.0, 6.0), identity, 5.0),
            ToolPoseProblem::TooFar);
}

}  // namespace
}  // namespace surgical_sim::core
