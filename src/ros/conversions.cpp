#include "surgical_sim/ros/conversions.h"

#include <ros/console.h>

namespace surgical_sim::ros_layer {

Eigen::Vector3d toEigen(const geometry_msgs::Point& p) { return {p.x, p.y, p.z}; }

Eigen::Vector3d toEigen(const geometry_msgs::Vector3& v) { return {v.x, v.y, v.z}; }

Eigen::Isometry3d toEigen(const geometry_msgs::Pose& pose) {
  const Eigen::Quaterniond q(pose.orientation.w, pose.orientation.x, pose.orientation.y,
                             pose.orientation.z);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = q.normalized().toRotationMatrix();
  t.translation() = toEigen(pose.position);
  return t;
}

namespace {

/// A message with fields x, y, z (Point, Vector3) holding v.
template <typename Msg>
Msg xyzMsg(const Eigen::Vector3d& v) {
  Msg m;
  m.x = v.x();
  m.y = v.y();
  m.z = v.z();
  return m;
}

}  // namespace

geometry_msgs::Point toPointMsg(const Eigen::Vector3d& p) {
  return xyzMsg<geometry_msgs::Point>(p);
}

geometry_msgs::Vector3 toVector3Msg(const Eigen::Vector3d& v) {
  return xyzMsg<geometry_msgs::Vector3>(v);
}

geometry_msgs::Pose toPoseMsg(const Eigen::Isometry3d& pose) {
  geometry_msgs::Pose m;
  m.position = toPointMsg(pose.translation());
  const Eigen::Quaterniond q(pose.linear());
  m.orientation.w = q.w();
  m.orientation.x = q.x();
  m.orientation.y = q.y();
  m.orientation.z = q.z();
  return m;
}

PoseProblem poseProblem(const geometry_msgs::Pose& pose, double max_distance) {
  return core::toolPoseProblem(toEigen(pose.position),
                               Eigen::Vector4d(pose.orientation.w, pose.orientation.x,
                                               pose.orientation.y, pose.orientation.z),
                               max_distance);
}

bool acceptPose(const geometry_msgs::Pose& pose, double max_distance, const char* node) {
  switch (poseProblem(pose, max_distance)) {
    case PoseProblem::None:
      return true;
    case PoseProblem::NonFinitePosition:
      ROS_WARN_THROTTLE_NAMED(1.0, node, "rejected tool pose: NaN/Inf position");
      break;
    case PoseProblem::BadQuaternion:
      ROS_WARN_THROTTLE_NAMED(1.0, node,
                              "rejected tool pose: zero or non-finite quaternion (norm must be in "
                              "[0.5, 2])");
      break;
    case PoseProblem::TooFar:
      ROS_WARN_THROTTLE_NAMED(1.0, node,
                              "rejected tool pose: farther than %.3g m (~max_tool_distance) from "
                              "the origin",
                              max_distance);
      break;
  }
  return false;
}

}  // namespace surgical_sim::ros_layer
