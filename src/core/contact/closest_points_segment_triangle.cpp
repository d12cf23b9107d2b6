#include "surgical_sim/core/contact/closest_points_segment_triangle.h"

#include <Eigen/Geometry>

#include "surgical_sim/core/contact/closest_point_on_triangle.h"
#include "surgical_sim/core/contact/closest_points_segment_segment.h"

namespace surgical_sim::core {
namespace {

/// Barycentric coordinates above -kBarycentricRoundOff count as inside (crossing points on an
/// edge or vertex are then found in every adjacent triangle) [-].
constexpr double kBarycentricRoundOff = 1e-12;

/// Replaces best by the pair (t, w) if it is closer.
void keepCloser(double t, const Eigen::Vector3d& w, const Eigen::Vector3d& a,
                const Eigen::Vector3d& b, const Eigen::Vector3d& v0, const Eigen::Vector3d& v1,
                const Eigen::Vector3d& v2, SegmentTriangleClosest& best) {
  const Eigen::Vector3d on_segment = a + t * (b - a);
  const Eigen::Vector3d on_triangle = w[0] * v0 + w[1] * v1 + w[2] * v2;
  const double distance_squared = (on_segment - on_triangle).squaredNorm();
  if (distance_squared >= best.distance_squared) return;
  best.t = t;
  best.barycentric = w;
  best.point_segment = on_segment;
  best.point_triangle = on_triangle;
  best.distance_squared = distance_squared;
}

}  // namespace

SegmentTriangleClosest closestPointsSegmentTriangle(const Eigen::Vector3d& a,
                                                    const Eigen::Vector3d& b,
                                                    const Eigen::Vector3d& v0,
                                                    const Eigen::Vector3d& v1,
                                                    const Eigen::Vector3d& v2) {
  SegmentTriangleClosest best;
  const Eigen::Vector3d normal = (v1 - v0).cross(v2 - v0);  // |normal| = 2 area
  const double area2_squared = normal.squaredNorm();
  if (area2_squared > 0.0) {
    const double da = normal.dot(a - v0);
    const double db = normal.dot(b - v0);
    if (da * db <= 0.0 && da != db) {
      const double t = da / (da - db);
      const Eigen::Vector3d p = a + t * (b - a);
      const Eigen::Vector3d w(normal.dot((v1 - p).cross(v2 - p)) / area2_squared,
                              normal.dot((v2 - p).cross(v0 - p)) / area2_squared,
                              normal.dot((v0 - p).cross(v1 - p)) / area2_squared);
      // Crossings on an edge or vertex (within round-off) count for every adjacent triangle.
      if ((w.array() >= -kBarycentricRoundOff).all()) {
        const Eigen::Vector3d clamped = w.cwiseMax(0.0);
        best.t = t;
        best.barycentric = clamped / clamped.sum();
        best.point_segment = p;
        best.point_triangle =
            best.barycentric[0] * v0 + best.barycentric[1] * v1 + best.barycentric[2] * v2;
        best.distance_squared = 0.0;
        best.intersects = true;
        return best;
      }
    }
  }
  const TrianglePointClosest at_a = closestPointOnTriangle(v0, v1, v2, a);
  best.t = 0.0;
  best.barycentric = at_a.barycentric;
  best.point_segment = a;
  best.point_triangle = at_a.point;
  best.distance_squared = at_a.distance_squared;
  keepCloser(1.0, closestPointOnTriangle(v0, v1, v2, b).barycentric, a, b, v0, v1, v2, best);
  const SegmentSegmentClosest e01 = closestPointsSegmentSegment(a, b, v0, v1);
  keepCloser(e01.s, {1.0 - e01.t, e01.t, 0.0}, a, b, v0, v1, v2, best);
  const SegmentSegmentClosest e12 = closestPointsSegmentSegment(a, b, v1, v2);
  keepCloser(e12.s, {0.0, 1.0 - e12.t, e12.t}, a, b, v0, v1, v2, best);
  const SegmentSegmentClosest e20 = closestPointsSegmentSegment(a, b, v2, v0);
  keepCloser(e20.s, {e20.t, 0.0, 1.0 - e20.t}, a, b, v0, v1, v2, best);
  return best;
}

}  // namespace surgical_sim::core
