#include "surgical_sim/core/cutting/blade_edge_detection.h"

#include <cstddef>

#include "index_at.h"
#include "surgical_sim/core/cutting/edge_sweep_ccd.h"

namespace surgical_sim::core {

namespace {

using cutting_index::at;
using cutting_index::toSize;

Eigen::Vector3d nodeAt(const Eigen::VectorXd& x, int node) { return x.segment<3>(3 * node); }

/// Outcode of every node against the box [lo, hi] (see detectBladeEdgeCrossings()).
void sweptBoxOutcodes(const Eigen::VectorXd& x_start, const Eigen::VectorXd& x_end,
                      const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      std::vector<std::uint8_t>& outcode) {
  const auto n = static_cast<int>(x_start.size() / 3);
  outcode.resize(toSize(n));
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector3d p0 = nodeAt(x_start, v), p1 = nodeAt(x_end, v);
    std::uint8_t code = 0;
    for (int d = 0; d < 3; ++d) {
      if (p0[d] < lo[d] && p1[d] < lo[d]) code |= 1 << (2 * d);
      if (p0[d] > hi[d] && p1[d] > hi[d]) code |= 1 << (2 * d + 1);
    }
    at(outcode, v) = code;
  }
}

/// Parameter s of the earliest crossing of edge (a, b) with any blade segment, or -1 for none.
double earliestCrossing(const BladeSweep& sweep, const Eigen::VectorXd& x_start,
                        const Eigen::VectorXd& x_end, int a, int b, double tolerance) {
  const Eigen::Vector3d a0 = nodeAt(x_start, a), b0 = nodeAt(x_start, b);
  const Eigen::Vector3d a1 = nodeAt(x_end, a), b1 = nodeAt(x_end, b);
  double best_t = 2.0, s = -1.0;
  for (Eigen::Index k = 0; k + 1 < sweep.start.cols(); ++k) {
    const auto hit = edgeSweepCrossing(sweep.start.col(k), sweep.start.col(k + 1), sweep.end.col(k),
                                       sweep.end.col(k + 1), a0, b0, a1, b1, tolerance);
    if (hit && hit->t < best_t) {
      best_t = hit->t;
      s = hit->s;
    }
  }
  return best_t <= 1.0 ? s : -1.0;
}

}  // namespace

std::vector<BladeEdgeCrossing> detectBladeEdgeCrossings(
    const BladeSweep& sweep, const Eigen::VectorXd& x_start, const Eigen::VectorXd& x_end,
    const std::vector<std::array<int, 2>>& edges, const std::vector<std::uint8_t>& skip,
    double tolerance, std::vector<std::uint8_t>& outcode) {
  const Eigen::Vector3d lo =
      sweep.start.rowwise().minCoeff().cwiseMin(sweep.end.rowwise().minCoeff()).array() - tolerance;
  const Eigen::Vector3d hi =
      sweep.start.rowwise().maxCoeff().cwiseMax(sweep.end.rowwise().maxCoeff()).array() + tolerance;
  sweptBoxOutcodes(x_start, x_end, lo, hi, outcode);
  std::vector<BladeEdgeCrossing> crossings;
  for (std::size_t id = 0; id < edges.size(); ++id) {
    const auto [a, b] = edges[id];
    if (skip[id] || a < 0 || (at(outcode, a) & at(outcode, b))) continue;
    const double s = earliestCrossing(sweep, x_start, x_end, a, b, tolerance);
    if (s >= 0.0) crossings.push_back({static_cast<int>(id), s});
  }
  return crossings;
}

}  // namespace surgical_sim::core
