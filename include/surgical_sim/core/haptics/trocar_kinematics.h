#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "surgical_sim/core/haptics/trocar_geometry.h"
#include "surgical_sim/core/haptics/trocar_joints.h"

namespace surgical_sim::core {

/// Forward kinematics and geometric Jacobian of the 5-DoF active trocar (a remote-centre-of-motion
/// chain). Frames: F = trocar frame at the fulcrum (z into the patient), T = tool tip (z along
/// the shaft, pointing distally). Chain, identical to urdf/active_trocar.urdf:
///
///   X_FT(q) = Rx(pitch) * Ry(yaw) * Rz(spin) * Tz(insertion + tip_offset)
///
/// i.e. pitch about x_F, yaw about the y axis after pitch, spin about the shaft axis, insertion
/// along the shaft; grip moves only the jaws. Shaft axis in F:
///   e_F = (sin yaw, -sin pitch cos yaw, cos pitch cos yaw).
/// Stateless and allocation-free; every method is safe to call from the 1 kHz loop.
class TrocarKinematics {
 public:
  /// @throws std::invalid_argument if the geometry is invalid (see validateTrocarGeometry).
  explicit TrocarKinematics(const TrocarGeometry& geometry);

  const TrocarGeometry& geometry() const { return geometry_; }

  /// Pose of the tool tip T in the trocar frame F (X_FT) for joint positions q (5x1).
  Eigen::Isometry3d toolTipPose(const TrocarJointVector& q) const;

  /// Geometric Jacobian of the tool tip expressed in F (6x5): [v_FT; w_FT] = J_FT(q) qdot, with
  /// v the velocity of the tip point [m/s] and w the tool's angular velocity [rad/s]. The grip
  /// column is zero.
  TrocarJacobian jacobian(const TrocarJointVector& q) const;

  /// Unit shaft axis e_F in F (3x1) pointing distally (into the patient) [-].
  Eigen::Vector3d shaftAxis(const TrocarJointVector& q) const;

  /// Distance from the fulcrum (origin of F) to the shaft line [m], computed from the forward
  /// kinematics (tip position and tip z axis). Zero by construction: the fulcrum constraint.
  double fulcrumDistance(const TrocarJointVector& q) const;

  /// Signed depth of the tool tip below the fulcrum along the shaft, insertion + tip_offset [m].
  double tipDepth(const TrocarJointVector& q) const;

 private:
  TrocarGeometry geometry_;
};

}  // namespace surgical_sim::core
