#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "surgical_sim/ros/conversions.h"

namespace surgical_sim::ros_layer {
namespace {

TEST(Conversions, PoseRoundTripPreservesTransform) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(0.1, -0.2, 0.3);
  const Eigen::Isometry3d back = toEigen(toPoseMsg(t));
  EXPECT_LT((back.matrix() - t.matrix()).norm(), 1e-12);
}

TEST(Conversions, UnnormalisedQuaternionIsNormalised) {
  geometry_msgs::Pose pose;
  pose.orientation.w = 2.0;  // identity rotation scaled by 2
  const Eigen::Isometry3d t = toEigen(pose);
  EXPECT_LT((t.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(Conversions, PoseProblemTellsEachKindOfBadPoseApart) {
  geometry_msgs::Pose pose;
  pose.orientation.w = 1.0;
  EXPECT_EQ(poseProblem(pose, 10.0), PoseProblem::None);
  pose.position.x = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(poseProblem(pose, 10.0), PoseProblem::NonFinitePosition);
  pose.position.x = std::numeric_limits<double>::infinity();
  EXPECT_EQ(poseProblem(pose, 10.0), PoseProblem::NonFinitePosition);
  pose.position.x = 100.0;
  EXPECT_EQ(poseProblem(pose, 10.0), PoseProblem::TooFar);
  pose.position.x = 0.0;
  pose.orientation.w = 0.0;
  EXPECT_EQ(poseProblem(pose, 10.0), PoseProblem::BadQuaternion);
  pose.orientation.w = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(poseProblem(pose, 10.0), PoseProblem::BadQuaternion);
  pose.orientation.w = 1.0;
  pose.orientation.z = std::numeric_limits<double>::infinity();
  EXPECT_EQ(poseProblem(pose, 10.0), PoseProblem::BadQuaternion);
}

}  // namespace
}  // namespace surgical_sim::ros_layer
