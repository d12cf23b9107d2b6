#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Why a commanded tool pose is rejected before it may reach a simulation (None: usable).
enum class ToolPoseProblem {
  None,
  NonFinitePosition,  ///< a position coordinate is NaN or Inf
  BadQuaternion,      ///< a quaternion component is not finite, or its norm is outside [0.5, 2]
                      ///< (normalising it would not be meaningful)
  TooFar,             ///< the position is farther than max_distance [m] from the origin
};

/// The check every commanded tool pose passes before it may reach a simulation (the nodes apply
/// it at their boundary, the in-process fuzzers apply it too): classifies the position p [m] and
/// the quaternion q_wxyz = (w, x, y, z), checking in the order of ToolPoseProblem.
ToolPoseProblem toolPoseProblem(const Eigen::Vector3d& p, const Eigen::Vector4d& q_wxyz,
                                double max_distance);

/// toolPoseProblem(p, q_wxyz, max_distance) == ToolPoseProblem::None.
bool isUsableToolPose(const Eigen::Vector3d& p, const Eigen::Vector4d& q_wxyz, double max_distance);

}  // namespace surgical_sim::core
