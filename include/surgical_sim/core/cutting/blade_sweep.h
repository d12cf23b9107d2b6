#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Motion of a blade polyline over one step: point i moves linearly from start.col(i) at the
/// step start to end.col(i) at the step end. Points are in the tissue frame [m].
struct BladeSweep {
  Eigen::Matrix3Xd start;  ///< polyline at the step start [m], shape 3 x k, k >= 2
  Eigen::Matrix3Xd end;    ///< polyline at the step end [m], shape 3 x k (same k)
};

/// @throws std::invalid_argument naming "blade_sweep.start" / "blade_sweep.end" when the
///         polyline has fewer than 2 points, the shapes differ, or a coordinate is not finite.
void validateBladeSweep(const BladeSweep& sweep);

}  // namespace surgical_sim::core
