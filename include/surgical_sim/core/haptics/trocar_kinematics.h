#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "surgical_sim/core/haptics/trocar_chain.h"
#include "surgical_sim/core/haptics/trocar_joints.h"

namespace surgical_sim::core {

/// Forward kinematics and geometric Jacobian of the 5-DoF active trocar (a remote-centre-of-motion
/// chain), evaluated on the joint chain its URDF gives (TrocarChain): every joint is its origin
/// followed by the motion about/along its axis. Frames: F = trocar frame at the fulcrum (z into
/// the patient), T = tool tip (z along the shaft, pointing distally). For urdf/active_trocar.urdf:
///
///   X_FT(q) = Rx(pitch) * Ry(yaw) * Rz(spin) * Tz(insertion + 0.020 m)
///
/// Grip moves only the jaws. Stateless and allocation-free; every method is safe to call from the
/// 1 kHz loop.
class TrocarKinematics {
 public:
  /// @throws std::invalid_argument if the chain is invalid (see validateTrocarChain).
  explicit TrocarKinematics(const TrocarChain& chain);

  const TrocarChain& chain() const { return chain_; }

  /// Pose of the tool tip T in the trocar frame F (X_FT) for joint positions q (5x1).
  Eigen::Isometry3d toolTipPose(const TrocarJointVector& q) const;

  /// Geometric Jacobian of the tool tip expressed in F (6x5): [v_FT; w_FT] = J_FT(q) qdot, with
  /// v the velocity of the tip point [m/s] and w the tool's angular velocity [rad/s]. The grip
  /// column is zero.
  TrocarJacobian jacobian(const TrocarJointVector& q) const;

  /// Unit shaft axis e_F in F (3x1) pointing distally (into the patient) [-]: the insertion
  /// joint's axis.
  Eigen::Vector3d shaftAxis(const TrocarJointVector& q) const;

  /// Distance from the fulcrum (origin of F) to the shaft line [m], computed from the forward
  /// kinematics (tip position and tip z axis). Zero for a remote-centre-of-motion chain.
  double fulcrumDistance(const TrocarJointVector& q) const;

  /// Signed depth of the tool tip below the fulcrum along the shaft, p_FT . e_F [m].
  double tipDepth(const TrocarJointVector& q) const;

 private:
  /// Pose in F of the frame of chain joint `joint` (before its motion), for q (5x1).
  Eigen::Isometry3d jointFrame(const TrocarJointVector& q, int joint) const;

  TrocarChain chain_;
};

}  // namespace surgical_sim::core
