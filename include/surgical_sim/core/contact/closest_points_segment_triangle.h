#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Closest points of a segment and a triangle.
struct SegmentTriangleClosest {
  double t = 0.0;                                            ///< segment parameter in [0, 1]
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();     ///< triangle weights, >= 0, sum 1
  Eigen::Vector3d point_segment = Eigen::Vector3d::Zero();   ///< a + t (b - a) [m]
  Eigen::Vector3d point_triangle = Eigen::Vector3d::Zero();  ///< sum_k w_k v_k [m]
  double distance_squared = 0.0;                             ///< [m^2]
  bool intersects = false;  ///< the segment crosses the triangle (distance 0)
};

/// Exact closest points between the segment [a, b] and the triangle (v0, v1, v2), one frame,
/// [m]. If the segment crosses the triangle's interior, the crossing point is returned with
/// distance 0. Otherwise the minimum is reached with a segment end point or on a triangle edge,
/// so it is the least of: both end points against the triangle and the segment against the three
/// edges. Parallel segments, degenerate segments (a point) and degenerate (zero-area) triangles
/// are handled. Stateless, allocation-free.
SegmentTriangleClosest closestPointsSegmentTriangle(const Eigen::Vector3d& a,
                                                    const Eigen::Vector3d& b,
                                                    const Eigen::Vector3d& v0,
                                                    const Eigen::Vector3d& v1,
                                                    const Eigen::Vector3d& v2);

}  // namespace surgical_sim::core
