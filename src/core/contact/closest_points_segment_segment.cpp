#include "surgical_sim/core/contact/closest_points_segment_segment.h"

#include <algorithm>

namespace surgical_sim::core {

SegmentSegmentClosest closestPointsSegmentSegment(const Eigen::Vector3d& p0,
                                                  const Eigen::Vector3d& p1,
                                                  const Eigen::Vector3d& q0,
                                                  const Eigen::Vector3d& q1) {
  const Eigen::Vector3d d1 = p1 - p0;
  const Eigen::Vector3d d2 = q1 - q0;
  const Eigen::Vector3d r = p0 - q0;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  double s = 0.0;
  double t = 0.0;
  if (a <= 0.0 && e <= 0.0) {
    // both degenerate: s = t = 0
  } else if (a <= 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denominator = a * e - b * b;  // >= 0; 0 when parallel
      // Parallel: any s works; s = 0 then the matching t.
      s = denominator > 1e-14 * a * e ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  SegmentSegmentClosest result;
  result.s = s;
  result.t = t;
  result.point_p = p0 + s * d1;
  result.point_q = q0 + t * d2;
  result.distance_squared = (result.point_p - result.point_q).squaredNorm();
  return result;
}

}  // namespace surgical_sim::core
