#pragma once

#include <geometry_msgs/Point.h>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Vector3.h>

#include <Eigen/Geometry>

#include "surgical_sim/core/common/tool_pose_check.h"

namespace surgical_sim::ros_layer {

/// geometry_msgs <-> Eigen, SI units, no frame change (the caller resolves frames with tf2).
Eigen::Vector3d toEigen(const geometry_msgs::Point& p);
Eigen::Vector3d toEigen(const geometry_msgs::Vector3& v);
/// @return the pose as an isometry; the quaternion is normalised.
Eigen::Isometry3d toEigen(const geometry_msgs::Pose& pose);
geometry_msgs::Point toPointMsg(const Eigen::Vector3d& p);
geometry_msgs::Vector3 toVector3Msg(const Eigen::Vector3d& v);
geometry_msgs::Pose toPoseMsg(const Eigen::Isometry3d& pose);

/// Why a tool pose is rejected at the node boundary (None: usable).
using PoseProblem = core::ToolPoseProblem;

/// core::toolPoseProblem() of the message's position and quaternion.
PoseProblem poseProblem(const geometry_msgs::Pose& pose, double max_distance);

/// True if `pose` is usable; otherwise logs a throttled warning (1 s) on logger `node` whose text
/// is specific to the problem ("rejected tool pose: NaN/Inf position", "...: zero or non-finite
/// quaternion", "...: farther than <max_distance> m (~max_tool_distance) from the origin").
bool acceptPose(const geometry_msgs::Pose& pose, double max_distance, const char* node);

}  // namespace surgical_sim::ros_layer
