#include "surgical_sim/core/haptics/trocar_kinematics.h"

#include <cstddef>

namespace surgical_sim::core {
namespace {

/// Motion of a joint by q about/along its axis (joint frame before -> after the motion).
Eigen::Isometry3d jointMotion(const TrocarChainJoint& joint, double q) {
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  if (joint.type == TrocarJointType::Prismatic)
    M.translation() = q * joint.axis;
  else
    M.linear() = Eigen::AngleAxisd(q, joint.axis).toRotationMatrix();
  return M;
}

}  // namespace

TrocarKinematics::TrocarKinematics(const TrocarChain& chain) : chain_(chain) {
  validateTrocarChain(chain_);
}

Eigen::Isometry3d TrocarKinematics::jointFrame(const TrocarJointVector& q, int joint) const {
  Eigen::Isometry3d X_FJ = Eigen::Isometry3d::Identity();
  for (int j = 0; j < joint; ++j) {
    const TrocarChainJoint& chain_joint = chain_.joints[static_cast<std::size_t>(j)];
    X_FJ = X_FJ * chain_joint.X_PJ * jointMotion(chain_joint, q[j]);
  }
  return X_FJ * chain_.joints[static_cast<std::size_t>(joint)].X_PJ;
}

Eigen::Isometry3d TrocarKinematics::toolTipPose(const TrocarJointVector& q) const {
  constexpr int kLast = kTrocarChainJointCount - 1;
  return jointFrame(q, kLast) * jointMotion(chain_.joints[kLast], q[kLast]) * chain_.X_JT;
}

Eigen::Vector3d TrocarKinematics::shaftAxis(const TrocarJointVector& q) const {
  return jointFrame(q, kTrocarInsertion).linear() * chain_.joints[kTrocarInsertion].axis;
}

double TrocarKinematics::tipDepth(const TrocarJointVector& q) const {
  return toolTipPose(q).translation().dot(shaftAxis(q));
}

TrocarJacobian TrocarKinematics::jacobian(const TrocarJointVector& q) const {
  // Column j: axis a_j in F through the joint origin o_j; revolute [a_j x (p_FT - o_j); a_j],
  // prismatic [a_j; 0].
  const Eigen::Vector3d p_FT = toolTipPose(q).translation();
  TrocarJacobian J = TrocarJacobian::Zero();
  for (int j = 0; j < kTrocarChainJointCount; ++j) {
    const TrocarChainJoint& joint = chain_.joints[static_cast<std::size_t>(j)];
    const Eigen::Isometry3d X_FJ = jointFrame(q, j);
    const Eigen::Vector3d a_F = X_FJ.linear() * joint.axis;
    if (joint.type == TrocarJointType::Prismatic) {
      J.block<3, 1>(0, j) = a_F;
    } else {
      J.block<3, 1>(0, j) = a_F.cross(p_FT - X_FJ.translation());
      J.block<3, 1>(3, j) = a_F;
    }
  }
  return J;
}

double TrocarKinematics::fulcrumDistance(const TrocarJointVector& q) const {
  const Eigen::Isometry3d X_FT = toolTipPose(q);
  const Eigen::Vector3d p_FT = X_FT.translation();
  const Eigen::Vector3d z_FT = X_FT.linear().col(2);
  // Distance from the origin to the line {p_FT + s z_FT}.
  return (p_FT - p_FT.dot(z_FT) * z_FT).norm();
}

}  // namespace surgical_sim::core
