#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Closest point of a segment to a point.
struct SegmentPointClosest {
  double t = 0.0;                                   ///< segment parameter in [0, 1]
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< a + t (b - a) [m]
  double distance_squared = 0.0;                    ///< |point - p|^2 [m^2]
};

/// Closest point to p on the segment [a, b] (all in one frame, [m]). A degenerate segment
/// (a == b) gives t = 0. Stateless, allocation-free.
SegmentPointClosest closestPointOnSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& p);

}  // namespace surgical_sim::core
