#include "surgical_sim/core/contact/closest_point_on_triangle.h"

#include "surgical_sim/core/contact/closest_point_on_segment.h"

namespace surgical_sim::core {
namespace {

TrianglePointClosest fromBarycentric(const Eigen::Vector3d& v0, const Eigen::Vector3d& v1,
                                     const Eigen::Vector3d& v2, const Eigen::Vector3d& p,
                                     const Eigen::Vector3d& w) {
  TrianglePointClosest result;
  result.barycentric = w;
  result.point = w[0] * v0 + w[1] * v1 + w[2] * v2;
  result.distance_squared = (result.point - p).squaredNorm();
  return result;
}

/// Degenerate triangle: the closest of the three edges.
TrianglePointClosest closestOnEdges(const Eigen::Vector3d& v0, const Eigen::Vector3d& v1,
                                    const Eigen::Vector3d& v2, const Eigen::Vector3d& p) {
  const SegmentPointClosest e01 = closestPointOnSegment(v0, v1, p);
  const SegmentPointClosest e12 = closestPointOnSegment(v1, v2, p);
  const SegmentPointClosest e20 = closestPointOnSegment(v2, v0, p);
  Eigen::Vector3d w(1.0 - e01.t, e01.t, 0.0);
  double best = e01.distance_squared;
  if (e12.distance_squared < best) {
    best = e12.distance_squared;
    w = Eigen::Vector3d(0.0, 1.0 - e12.t, e12.t);
  }
  if (e20.distance_squared < best) w = Eigen::Vector3d(e20.t, 0.0, 1.0 - e20.t);
  return fromBarycentric(v0, v1, v2, p, w);
}

}  // namespace

TrianglePointClosest closestPointOnTriangle(const Eigen::Vector3d& v0, const Eigen::Vector3d& v1,
                                            const Eigen::Vector3d& v2, const Eigen::Vector3d& p) {
  const Eigen::Vector3d ab = v1 - v0;
  const Eigen::Vector3d ac = v2 - v0;
  const Eigen::Vector3d corner[3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
  // p is in the Voronoi region of edge (a, b) when its barycentric area opposite the edge is
  // <= 0 and its projections on the edge from a and from b are da >= 0 >= db; the closest point
  // is then a + s (b - a), s = da / (da - db).
  const auto inEdgeRegion = [](double area, double da, double db) {
    return area <= 0.0 && da >= 0.0 && db <= 0.0 && da - db > 0.0;
  };
  const auto onEdge = [&](int a, int b, double da, double db) {
    const double s = da / (da - db);
    return fromBarycentric(v0, v1, v2, p, (1.0 - s) * corner[a] + s * corner[b]);
  };
  const double d1 = ab.dot(p - v0);
  const double d2 = ac.dot(p - v0);
  if (d1 <= 0.0 && d2 <= 0.0) return fromBarycentric(v0, v1, v2, p, corner[0]);
  const double d3 = ab.dot(p - v1);
  const double d4 = ac.dot(p - v1);
  if (d3 >= 0.0 && d4 <= d3) return fromBarycentric(v0, v1, v2, p, corner[1]);
  const double vc = d1 * d4 - d3 * d2;
  if (inEdgeRegion(vc, d1, d3)) return onEdge(0, 1, d1, d3);
  const double d5 = ab.dot(p - v2);
  const double d6 = ac.dot(p - v2);
  if (d6 >= 0.0 && d5 <= d6) return fromBarycentric(v0, v1, v2, p, corner[2]);
  const double vb = d5 * d2 - d1 * d6;
  if (inEdgeRegion(vb, d2, d6)) return onEdge(0, 2, d2, d6);
  const double va = d3 * d6 - d5 * d4;
  if (inEdgeRegion(va, d4 - d3, d6 - d5)) return onEdge(1, 2, d4 - d3, d6 - d5);
  const double sum = va + vb + vc;  // = |ab x ac|^2 >= 0
  if (!(sum > 0.0)) return closestOnEdges(v0, v1, v2, p);
  const double v = vb / sum;
  const double w = vc / sum;
  return fromBarycentric(v0, v1, v2, p, {1.0 - v - w, v, w});
}

}  // namespace surgical_sim::core
