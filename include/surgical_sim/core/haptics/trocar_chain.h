#pragma once

#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace surgical_sim::core {

/// How a trocar joint moves its child link (URDF joint types).
enum class TrocarJointType {
  Revolute,    ///< rotation about the axis within position limits [rad]
  Continuous,  ///< rotation about the axis without position limits [rad]
  Prismatic,   ///< translation along the axis [m]
};

/// One moving joint of the chain from the trocar frame F to the tool tip T.
struct TrocarChainJoint {
  TrocarJointType type = TrocarJointType::Revolute;
  /// Pose of the joint frame in the frame of the previous moving joint's child link (or in F for
  /// the first joint): the joint's URDF origin composed with every fixed joint before it.
  Eigen::Isometry3d X_PJ = Eigen::Isometry3d::Identity();
  /// Unit axis of the motion in the joint frame [-], 3x1.
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
};

/// Number of joints on the chain from F to the tool tip: pitch, yaw, spin, insertion (the grip
/// joint moves only the jaws, not the tip).
inline constexpr int kTrocarChainJointCount = 4;

/// Kinematic chain of the active trocar as its URDF describes it (readTrocarUrdf). Frames:
/// F = trocar frame (URDF base link, origin at the fulcrum), T = tool tip (URDF tip link). With
/// M_i(q_i) the motion of joint i (rotation by q_i about axis_i, or translation q_i axis_i):
///
///   X_FT(q) = X_PJ[0] M_0(pitch) X_PJ[1] M_1(yaw) X_PJ[2] M_2(spin) X_PJ[3] M_3(insertion) X_JT
///
/// There are no silent defaults: a default-constructed chain holds NaN and fails validation.
struct TrocarChain {
  std::array<TrocarChainJoint, kTrocarChainJointCount> joints;  ///< pitch, yaw, spin, insertion
  /// Pose of T in the insertion joint's child link: the fixed joints from there to the tip.
  Eigen::Isometry3d X_JT;

  TrocarChain();
};

/// @throws std::invalid_argument naming "trocar.chain.<joint>.X_PJ", "trocar.chain.<joint>.axis"
/// or "trocar.chain.X_JT" if a transform is not a finite rigid transform or an axis is not a
/// finite unit vector, or "trocar.chain.<joint>.type" if pitch/yaw are not revolute, spin not
/// continuous or insertion not prismatic.
void validateTrocarChain(const TrocarChain& chain);

}  // namespace surgical_sim::core
