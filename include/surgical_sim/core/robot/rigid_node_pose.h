#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace surgical_sim::core {

/// Pose of a rigid node (vertebra) N of a continuum robot in the robot_base frame B.
/// Increments are (dx, dtheta): p_BN += dx [m], R_BN <- exp(dtheta) R_BN [rad], dtheta in B, so
/// a point attached to the node moves by dp = dx + dtheta x (p - p_BN).
struct RigidNodePose {
  Eigen::Vector3d p_BN = Eigen::Vector3d::Zero();            ///< position [m]
  Eigen::Quaterniond q_BN = Eigen::Quaterniond::Identity();  ///< unit quaternion
};

}  // namespace surgical_sim::core
