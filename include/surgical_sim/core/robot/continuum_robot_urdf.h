#pragma once

#include <string>

#include "surgical_sim/core/robot/continuum_robot_description.h"

namespace surgical_sim::core {

/// tf frames of a continuum robot, as continuum_robot_controller publishes them: the base, one
/// frame per moving rigid node k = 1..n (child of the base) and the tip (child of node n).
struct ContinuumRobotFrames {
  std::string base = "robot_base";
  std::string link_prefix = "vertebra_";
  std::string tip = "robot_tip";

  /// Frame of rigid node k (1..n): link_prefix + k.
  std::string rigidNode(int k) const { return link_prefix + std::to_string(k); }
};

/// URDF of a continuum robot, one link per frame of `frames`: base link `frames.base` (root),
/// links rigidNode(1..n) hanging from it by floating joints "<link>_joint" whose origins are the
/// rest poses (k * vertebra_spacing along x), and the tip link from rigid node n by the floating
/// joint "<tip>_joint" (identity). Floating joints carry no joint state: robot_state_publisher
/// skips them and the controller's tf moves the links. Visuals: a disc of the vertebra thickness
/// per rigid node and a translucent cylinder for the soft section towards the previous node,
/// both of the tapered outer radius (outerRadiusAt).
/// @throws std::invalid_argument as validateContinuumRobotDescription.
std::string continuumRobotUrdf(const ContinuumRobotDescription& description,
                               const ContinuumRobotFrames& frames = ContinuumRobotFrames());

}  // namespace surgical_sim::core
