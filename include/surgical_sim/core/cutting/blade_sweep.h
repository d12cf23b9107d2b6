#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace surgical_sim::core {

/// Most points a blade polyline may have [-]: the cutter tests every blade segment against the
/// swept tissue edges each step, so a longer polyline only slows the simulation down.
constexpr Eigen::Index kMaxBladePoints = 1000;
/// Shortest accepted blade polyline [m] (sum of its segment lengths): a blade whose points all
/// coincide cannot cut anything.
constexpr double kMinBladeLength = 1e-6;

/// Motion of a blade polyline over one step: point i moves linearly from start.col(i) at the
/// step start to end.col(i) at the step end. Points are in the tissue frame [m].
struct BladeSweep {
  Eigen::Matrix3Xd start;  ///< polyline at the step start [m], shape 3 x k, 2 <= k <= 1000
  Eigen::Matrix3Xd end;    ///< polyline at the step end [m], shape 3 x k (same k)
};

/// Box of the blade's positions over the step (both polylines; linear motion stays inside it),
/// grown by `margin` [m] on every side.
Eigen::AlignedBox3d sweepBox(const BladeSweep& sweep, double margin = 0.0);

/// Checks one blade polyline [m] (any frame).
/// @throws std::invalid_argument naming `name` when it has fewer than 2 or more than
///         kMaxBladePoints points, a coordinate is not finite, or its total length is below
///         kMinBladeLength.
void validateBladePolyline(const std::string& name, const Eigen::Matrix3Xd& blade);

/// @throws std::invalid_argument naming "blade_sweep.start" / "blade_sweep.end" when either
///         polyline fails validateBladePolyline or the shapes differ.
void validateBladeSweep(const BladeSweep& sweep);

}  // namespace surgical_sim::core
