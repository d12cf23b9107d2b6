#pragma once

#include <geometry_msgs/Point.h>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Vector3.h>

#include <Eigen/Geometry>

namespace surgical_sim::ros_layer {

/// geometry_msgs <-> Eigen, SI units, no frame change (the caller resolves frames with tf2).
Eigen::Vector3d toEigen(const geometry_msgs::Point& p);
Eigen::Vector3d toEigen(const geometry_msgs::Vector3& v);
/// @return the pose as an isometry; the quaternion is normalised.
Eigen::Isometry3d toEigen(const geometry_msgs::Pose& pose);
geometry_msgs::Point toPointMsg(const Eigen::Vector3d& p);
geometry_msgs::Vector3 toVector3Msg(const Eigen::Vector3d& v);
geometry_msgs::Pose toPoseMsg(const Eigen::Isometry3d& pose);

/// core::isUsableToolPose() of the message's position and quaternion: finite, quaternion norm
/// within [0.5, 2], position within `max_distance` [m] of the origin.
bool isUsablePose(const geometry_msgs::Pose& pose, double max_distance);

}  // namespace surgical_sim::ros_layer
