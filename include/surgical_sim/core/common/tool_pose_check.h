#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// The check every commanded tool pose passes before it may reach a simulation (the nodes apply
/// it at their boundary, the in-process fuzzers apply it too). True when the position p [m] and
/// the quaternion q_wxyz = (w, x, y, z) are finite, the quaternion's norm is within [0.5, 2] (so
/// normalising it is meaningful) and |p| <= max_distance [m] (absurd poses are rejected).
bool isUsableToolPose(const Eigen::Vector3d& p, const Eigen::Vector4d& q_wxyz, double max_distance);

}  // namespace surgical_sim::core
