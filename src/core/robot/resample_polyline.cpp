#include "surgical_sim/core/robot/resample_polyline.h"

#include <cmath>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

std::vector<Eigen::Vector3d> resamplePolyline(const std::vector<Eigen::Vector3d>& points,
                                              double spacing) {
  requirePositive("path.spacing", spacing, "m");
  if (points.empty()) throw std::invalid_argument("path.points must hold at least one point");
  for (const Eigen::Vector3d& p : points)
    if (!p.allFinite()) throw std::invalid_argument("path.points must be finite");
  std::vector<Eigen::Vector3d> out{points.front()};
  double carried = 0.0;  // arc length since the last output [m]
  for (size_t i = 1; i < points.size(); ++i) {
    const Eigen::Vector3d d = points[i] - points[i - 1];
    const double length = d.norm();
    double s = spacing - carried;  // arc position of the next output on this segment [m]
    for (; s <= length; s += spacing) out.push_back(points[i - 1] + d * (s / length));
    carried = length - (s - spacing);
  }
  if ((out.back() - points.back()).norm() > 1e-12 * spacing) out.push_back(points.back());
  return out;
}

}  // namespace surgical_sim::core
