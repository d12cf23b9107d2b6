#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Closest points of two segments.
struct SegmentSegmentClosest {
  double s = 0.0;                                     ///< parameter on [p0, p1], in [0, 1]
  double t = 0.0;                                     ///< parameter on [q0, q1], in [0, 1]
  Eigen::Vector3d point_p = Eigen::Vector3d::Zero();  ///< p0 + s (p1 - p0) [m]
  Eigen::Vector3d point_q = Eigen::Vector3d::Zero();  ///< q0 + t (q1 - q0) [m]
  double distance_squared = 0.0;                      ///< |point_p - point_q|^2 [m^2]
};

/// Closest points between the segments [p0, p1] and [q0, q1] (one frame, [m]) (Ericson,
/// Real-Time Collision Detection, 5.1.9). Parallel segments (one of the equally close pairs is
/// returned) and degenerate (point) segments are handled. Stateless, allocation-free.
SegmentSegmentClosest closestPointsSegmentSegment(const Eigen::Vector3d& p0,
                                                  const Eigen::Vector3d& p1,
                                                  const Eigen::Vector3d& q0,
                                                  const Eigen::Vector3d& q1);

}  // namespace surgical_sim::core
