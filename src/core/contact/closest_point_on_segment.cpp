#include "surgical_sim/core/contact/closest_point_on_segment.h"

#include <algorithm>

namespace surgical_sim::core {

SegmentPointClosest closestPointOnSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& p) {
  SegmentPointClosest result;
  const Eigen::Vector3d d = b - a;
  const double length_squared = d.squaredNorm();
  result.t = length_squared > 0.0 ? std::clamp((p - a).dot(d) / length_squared, 0.0, 1.0) : 0.0;
  result.point = a + result.t * d;
  result.distance_squared = (result.point - p).squaredNorm();
  return result;
}

}  // namespace surgical_sim::core
