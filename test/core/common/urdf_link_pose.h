// URDF forward kinematics walked generically through urdfdom's model, for the URDF tests.
#pragma once

#include <urdf_parser/urdf_parser.h>

#include <map>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

namespace surgical_sim::core::test {

/// Pose of `link` in `root` by URDF semantics, for any joint types: each joint is its origin
/// (xyz, rpy) followed by its motion about/along its axis (positions by joint name, default 0).
inline Eigen::Isometry3d urdfLinkPose(const urdf::ModelInterface& model, const std::string& root,
                                      std::string link,
                                      const std::map<std::string, double>& positions) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  while (link != root) {
    const urdf::LinkConstSharedPtr l = model.getLink(link);
    if (!l || !l->parent_joint) {
      ADD_FAILURE() << "link " << link << " does not hang below " << root;
      return X;
    }
    const urdf::Joint& j = *l->parent_joint;
    const urdf::Pose& o = j.parent_to_joint_origin_transform;
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
    origin.translation() = Eigen::Vector3d(o.position.x, o.position.y, o.position.z);
    double roll, pitch, yaw;
    o.rotation.getRPY(roll, pitch, yaw);
    origin.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                       Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                       Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                          .toRotationMatrix();
    const auto q = positions.find(j.name);
    const double value = q == positions.end() ? 0.0 : q->second;
    const Eigen::Vector3d axis = Eigen::Vector3d(j.axis.x, j.axis.y, j.axis.z).normalized();
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::CONTINUOUS)
      motion.linear() = Eigen::AngleAxisd(value, axis).toRotationMatrix();
    if (j.type == urdf::Joint::PRISMATIC) motion.translation() = value * axis;
    X = origin * motion * X;
    link = j.parent_link_name;
  }
  return X;
}

}  // namespace surgical_sim::core::test
