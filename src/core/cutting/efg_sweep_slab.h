#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <initializer_list>
#include <limits>

#include "surgical_sim/core/cutting/blade_sweep.h"

namespace surgical_sim::core::efg_sweep_slab {

/// The slab holding the sweep of one blade segment: the extent of its four corners (both ends at
/// the start and at the end of the step; the bilinear sweep lies in their hull, at every time)
/// along the swept quad's normal, grown by a margin.
struct SweepSlab {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< unit; zero: no slab (see sweepSlab)
  double lo = 0.0;                                   ///< [m]
  double hi = 0.0;                                   ///< [m]

  /// Distance along the normal from the points' extent to the slab [m]: 0 when some point (or
  /// the segment between two) lies within it, and 0 without a slab.
  double gap(std::initializer_list<Eigen::Vector3d> points) const {
    if (normal.squaredNorm() == 0.0) return 0.0;
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (const Eigen::Vector3d& p : points) {
      const double h = normal.dot(p);
      low = std::min(low, h);
      high = std::max(high, h);
    }
    return std::max({lo - high, low - hi, 0.0});
  }

  /// True when every point lies beyond the same face of the slab: nothing moving within their
  /// hull comes within the margin of the sweep. False without a slab.
  bool apart(std::initializer_list<Eigen::Vector3d> points) const { return gap(points) > 0.0; }

  /// Distance along the normal from the box [box_lo, box_hi] to the slab [m]: 0 when it meets it,
  /// and 0 without a slab.
  double boxGap(const Eigen::Vector3d& box_lo, const Eigen::Vector3d& box_hi) const {
    const double centre = normal.dot(0.5 * (box_lo + box_hi));
    const double half = normal.cwiseAbs().dot(0.5 * (box_hi - box_lo));
    return std::max({lo - (centre + half), centre - half - hi, 0.0});
  }
};

/// Slab of segment i (0 <= i < sweep.start.cols() - 1) of `sweep`, grown by margin [m] >= 0 plus
/// 1e-9 of the corners' extent (round-off). No slab (zero normal) when the segment moves along
/// itself or does not move.
inline SweepSlab sweepSlab(const BladeSweep& sweep, Eigen::Index i, double margin) {
  const Eigen::Vector3d c[4] = {sweep.start.col(i), sweep.start.col(i + 1), sweep.end.col(i),
                                sweep.end.col(i + 1)};
  const Eigen::Vector3d normal =
      (c[1] - c[0]).cross(c[2] - c[0]) + (c[3] - c[2]).cross(c[3] - c[1]);
  double extent = 0.0;
  for (const Eigen::Vector3d& corner : c) extent = std::max(extent, (corner - c[0]).norm());
  SweepSlab slab;
  if (!(normal.norm() > 1e-12 * extent * extent)) return slab;
  slab.normal = normal.normalized();
  slab.lo = std::numeric_limits<double>::infinity();
  slab.hi = -slab.lo;
  for (const Eigen::Vector3d& corner : c) {
    slab.lo = std::min(slab.lo, slab.normal.dot(corner));
    slab.hi = std::max(slab.hi, slab.normal.dot(corner));
  }
  slab.lo -= margin + 1e-9 * extent;
  slab.hi += margin + 1e-9 * extent;
  return slab;
}

}  // namespace surgical_sim::core::efg_sweep_slab
