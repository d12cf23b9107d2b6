#include "surgical_sim/core/haptics/trocar_kinematics.h"

#include <cmath>

namespace surgical_sim::core {

TrocarKinematics::TrocarKinematics(const TrocarGeometry& geometry) : geometry_(geometry) {
  validateTrocarGeometry(geometry_);
}

Eigen::Isometry3d TrocarKinematics::toolTipPose(const TrocarJointVector& q) const {
  const Eigen::Matrix3d R_FT = (Eigen::AngleAxisd(q[kTrocarPitch], Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(q[kTrocarYaw], Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(q[kTrocarSpin], Eigen::Vector3d::UnitZ()))
                                   .toRotationMatrix();
  Eigen::Isometry3d X_FT = Eigen::Isometry3d::Identity();
  X_FT.linear() = R_FT;
  X_FT.translation() = R_FT.col(2) * tipDepth(q);
  return X_FT;
}

Eigen::Vector3d TrocarKinematics::shaftAxis(const TrocarJointVector& q) const {
  const double sp = std::sin(q[kTrocarPitch]), cp = std::cos(q[kTrocarPitch]);
  const double sy = std::sin(q[kTrocarYaw]), cy = std::cos(q[kTrocarYaw]);
  return Eigen::Vector3d(sy, -sp * cy, cp * cy);
}

double TrocarKinematics::tipDepth(const TrocarJointVector& q) const {
  return q[kTrocarInsertion] + geometry_.tip_offset;
}

TrocarJacobian TrocarKinematics::jacobian(const TrocarJointVector& q) const {
  // Joint axes in F: pitch about x_F, yaw about Rx(pitch) y, spin and insertion along the shaft.
  // The three revolute axes pass through the fulcrum, so the linear column of a revolute joint
  // is a_i x p_FT, with p_FT = d e_F the tip position.
  const double sp = std::sin(q[kTrocarPitch]), cp = std::cos(q[kTrocarPitch]);
  const Eigen::Vector3d a_pitch = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d a_yaw(0.0, cp, sp);
  const Eigen::Vector3d e_F = shaftAxis(q);
  const Eigen::Vector3d p_FT = tipDepth(q) * e_F;

  TrocarJacobian J = TrocarJacobian::Zero();
  J.block<3, 1>(0, kTrocarPitch) = a_pitch.cross(p_FT);
  J.block<3, 1>(3, kTrocarPitch) = a_pitch;
  J.block<3, 1>(0, kTrocarYaw) = a_yaw.cross(p_FT);
  J.block<3, 1>(3, kTrocarYaw) = a_yaw;
  // Spin: e_F x p_FT = 0 exactly, the tip point does not translate.
  J.block<3, 1>(3, kTrocarSpin) = e_F;
  J.block<3, 1>(0, kTrocarInsertion) = e_F;
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
