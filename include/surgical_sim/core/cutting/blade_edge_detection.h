#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "surgical_sim/core/cutting/blade_sweep.h"

namespace surgical_sim::core {

/// A tissue edge crossed by the blade within one step.
struct BladeEdgeCrossing {
  int edge = 0;  ///< index into the candidate edge list
  double s =
      0.0;  ///< [-] crossing point on edge (a, b), from a, at the earliest crossing, in [0, 1]
};

/// Continuous detection of the tissue edges a blade polyline crosses within one step.
///
/// Swept-box rejection first: each node gets an outcode, bit 2d (2d + 1) set when it stays below
/// (above) the blade's swept bounding box along axis d over the whole step (box grown by
/// `tolerance`); an edge whose two nodes share a bit cannot reach the blade and is skipped. Every
/// remaining edge is tested against every blade segment with edgeSweepCrossing(); the crossing
/// with the earliest time over the segments gives s. The rejection is conservative: the result
/// equals testing every candidate edge with edgeSweepCrossing().
///
/// @param sweep blade motion over the step [m], tissue frame; must pass validateBladeSweep().
/// @param x_start, x_end node positions at the step start and end, node-major, size 3 n [m].
/// @param edges candidate edges as node pairs (a, b) into x; an edge with a < 0 is not tested.
/// @param skip per candidate edge, nonzero to leave it untested (e.g. already cut); same size.
/// @param tolerance distance at which the blade touches an edge [m], >= 0.
/// @param outcode scratch, resized to n (kept by the caller so a step allocates nothing for it).
/// @return the crossed edges, in increasing edge index. Cost O(n + edges tested x blade segments).
std::vector<BladeEdgeCrossing> detectBladeEdgeCrossings(
    const BladeSweep& sweep, const Eigen::VectorXd& x_start, const Eigen::VectorXd& x_end,
    const std::vector<std::array<int, 2>>& edges, const std::vector<std::uint8_t>& skip,
    double tolerance, std::vector<std::uint8_t>& outcode);

}  // namespace surgical_sim::core
