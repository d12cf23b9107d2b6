#pragma once

#include <vector>

#include <Eigen/Core>

namespace surgical_sim::core {

/// Points every `spacing` [m] of arc length along the polyline through `points` (in order),
/// starting at points.front() and ending exactly at points.back(): the targets of a path followed
/// at speed v with control period dt (spacing = v dt). One point in, that point out.
/// @param points waypoints [m], any frame, at least 1, finite.
/// @param spacing arc length between consecutive outputs [m], > 0.
/// @throws std::invalid_argument naming "path.points" (empty or not finite) or "path.spacing".
std::vector<Eigen::Vector3d> resamplePolyline(const std::vector<Eigen::Vector3d>& points,
                                              double spacing);

}  // namespace surgical_sim::core
