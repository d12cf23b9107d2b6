#pragma once

#include <Eigen/Core>
#include <optional>

namespace surgical_sim::core {

/// Earliest contact of a moving blade segment with a moving tissue edge within one step.
struct EdgeSweepHit {
  double t = 0.0;  ///< time of contact as a fraction of the step, in [0, 1]
  double s = 0.0;  ///< parameter along the tissue edge [e0, e1], in [0, 1]
  double u = 0.0;  ///< parameter along the blade segment [b0, b1], in [0, 1]
};

/// Continuous edge-edge test (Provot 1997): every endpoint moves linearly over the step, from
/// its `_start` position at t = 0 to its `_end` position at t = 1 (one frame, [m]). The blade
/// segment sweeps a bilinear (skew) quad; the tissue edge crosses it iff at some t both segments
/// meet. Candidate times are the roots in [0, 1] of the coplanarity cubic
///   f(t) = ((b1 - b0) x (e0 - b0)) . (e1 - b0),
/// found by bisection on the monotone pieces between the roots of f' (so a fast edge that crosses
/// the whole sweep within the step, a static blade with moving tissue, and tangent contacts
/// where f touches 0 without changing sign are all found). At each candidate the segments must
/// be closer than `tolerance` [m]. Coplanar motion (f identically 0) is sampled at 9 times.
/// Stateless, allocation-free.
/// @return the earliest hit, or nothing.
std::optional<EdgeSweepHit> edgeSweepCrossing(
    const Eigen::Vector3d& b0_start, const Eigen::Vector3d& b1_start, const Eigen::Vector3d& b0_end,
    const Eigen::Vector3d& b1_end, const Eigen::Vector3d& e0_start, const Eigen::Vector3d& e1_start,
    const Eigen::Vector3d& e0_end, const Eigen::Vector3d& e1_end, double tolerance);

/// Coefficients c (f(t) = c0 + c1 t + c2 t^2 + c3 t^3) of the coplanarity cubic of
/// edgeSweepCrossing() [m^3]. Exposed for testing.
Eigen::Vector4d coplanarityCubic(const Eigen::Vector3d& b0_start, const Eigen::Vector3d& b1_start,
                                 const Eigen::Vector3d& b0_end, const Eigen::Vector3d& b1_end,
                                 const Eigen::Vector3d& e0_start, const Eigen::Vector3d& e1_start,
                                 const Eigen::Vector3d& e0_end, const Eigen::Vector3d& e1_end);

}  // namespace surgical_sim::core
