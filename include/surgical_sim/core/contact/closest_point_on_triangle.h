#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Closest point of a triangle to a point.
struct TrianglePointClosest {
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();  ///< weights of (v0, v1, v2), >= 0, sum 1
  Eigen::Vector3d point = Eigen::Vector3d::Zero();        ///< sum_k barycentric_k v_k [m]
  double distance_squared = 0.0;                          ///< |point - p|^2 [m^2]
};

/// Closest point to p on the triangle (v0, v1, v2) (all in one frame, [m]), by Voronoi regions
/// (Ericson, Real-Time Collision Detection, 5.1.5). Degenerate (zero-area) triangles are handled
/// as the union of their edges. Stateless, allocation-free.
TrianglePointClosest closestPointOnTriangle(const Eigen::Vector3d& v0, const Eigen::Vector3d& v1,
                                            const Eigen::Vector3d& v2, const Eigen::Vector3d& p);

}  // namespace surgical_sim::core
