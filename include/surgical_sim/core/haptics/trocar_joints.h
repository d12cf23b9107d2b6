#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Joint indices of the 5-DoF active trocar, in chain order (Chendeb 2007, §5.3.2).
enum TrocarJoint : int {
  kTrocarPitch = 0,      ///< revolute about the trocar x axis [rad]
  kTrocarYaw = 1,        ///< revolute about the y axis after pitch [rad]
  kTrocarSpin = 2,       ///< revolute about the shaft axis [rad], continuous
  kTrocarInsertion = 3,  ///< prismatic along the shaft axis [m]
  kTrocarGrip = 4,       ///< jaw opening angle [rad]
};

/// Number of trocar joints.
inline constexpr int kTrocarJointCount = 5;

/// Joint vector q = (pitch [rad], yaw [rad], spin [rad], insertion [m], grip [rad]), shape 5x1.
/// Also used for joint velocities and joint efforts (pitch/yaw/spin/grip [N m], insertion [N]).
using TrocarJointVector = Eigen::Matrix<double, kTrocarJointCount, 1>;

/// Spatial 6-vector (linear part first, angular part second), shape 6x1: a twist (v [m/s];
/// omega [rad/s]) or a wrench (force [N]; moment [N m]).
using SpatialVector = Eigen::Matrix<double, 6, 1>;

/// Geometric Jacobian of the tool tip, shape 6x5: rows 0-2 map joint velocities to the linear
/// velocity of the tool-tip point [m/s], rows 3-5 to the angular velocity of the tool [rad/s].
using TrocarJacobian = Eigen::Matrix<double, 6, kTrocarJointCount>;

/// Short lower-case joint name ("pitch", "yaw", "spin", "insertion", "grip"); "unknown" otherwise.
const char* trocarJointName(int joint);

}  // namespace surgical_sim::core
