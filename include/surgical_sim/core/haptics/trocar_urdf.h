#pragma once

#include <array>
#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "surgical_sim/core/haptics/trocar_chain.h"
#include "surgical_sim/core/haptics/trocar_device_config.h"
#include "surgical_sim/core/haptics/trocar_joints.h"

namespace surgical_sim::core {

/// Which trocar of a URDF to read. Joints <joint_prefix>pitch, yaw, spin, insertion, grip; base
/// link (frame F, the fulcrum) `base_link`; tool-tip link <joint_prefix>tool_tip. The shipped
/// urdf/active_trocar.urdf holds base_link "trocar" and joint_prefix "trocar_"; a scene URDF holds
/// trocar T as base_link "T" and joint_prefix "T_".
struct TrocarUrdfNames {
  std::string base_link;
  std::string joint_prefix;
  std::string world_link = "world";  ///< parent link of the optional fixed joint placing F

  /// Contract names of trocar `name`: base link `name`, joint prefix `name` + "_".
  static TrocarUrdfNames forTrocar(const std::string& name);
};

/// Position limits, effort limit and friction of one joint as its URDF states them. Units follow
/// the joint: [rad], [N m], [N m s/rad] for revolute joints, [m], [N], [N s/m] for insertion.
struct TrocarUrdfJoint {
  std::string name;       ///< URDF joint name
  double lower = 0.0;     ///< <limit lower> (0 for the continuous spin joint)
  double upper = 0.0;     ///< <limit upper> (0 for the continuous spin joint)
  double effort = 0.0;    ///< <limit effort>, > 0
  double damping = 0.0;   ///< <dynamics damping>: viscous friction, >= 0
  double friction = 0.0;  ///< <dynamics friction>: Coulomb friction, >= 0
};

/// One trocar read from a URDF.
struct TrocarUrdf {
  TrocarChain chain;                                      ///< F -> tool tip (TrocarKinematics)
  std::array<TrocarUrdfJoint, kTrocarJointCount> joints;  ///< indexed by TrocarJoint
  /// Pose of F in the world link when the URDF holds a fixed joint from it to the base link.
  std::optional<Eigen::Isometry3d> X_WF;
};

/// Reads the trocar `names` from URDF text with urdfdom: the chain from the base link to the tip
/// link (origins composed with the fixed joints between, axes normalized), joint types, limits
/// (position, effort), dynamics (damping, friction) and, if present, the fixed joint from the
/// world link to the base link.
/// @throws std::invalid_argument naming the problem: text urdfdom cannot parse, a missing link or
/// joint, a wrong joint type (pitch, yaw, grip revolute; spin continuous; insertion prismatic),
/// a zero axis, a moving joint other than pitch/yaw/spin/insertion between base and tip, a base
/// link attached to anything but the world link by a fixed joint, missing <limit> or <dynamics>,
/// or limits outside what validateTrocarDeviceConfig accepts (pitch/yaw symmetric, within
/// +-70 deg; insertion [0, <= 0.30 m]; grip [0, <= 90 deg]; efforts > 0; frictions >= 0).
TrocarUrdf readTrocarUrdf(const std::string& urdf_xml, const TrocarUrdfNames& names);

/// Device configuration from the URDF (position limits, effort limits, damping -> viscous
/// friction, friction -> Coulomb friction) and the motors (gear ratio, rotor inertia, encoder).
/// @throws std::invalid_argument as validateTrocarDeviceConfig.
TrocarDeviceConfig makeTrocarDeviceConfig(const TrocarUrdf& urdf, const TrocarMotors& motors);

}  // namespace surgical_sim::core
