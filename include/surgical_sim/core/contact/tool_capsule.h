#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace surgical_sim::core {

/// Rigid tool modelled as a capsule: the set of points within radius of the segment from the tip
/// point T back along the tool's -z axis for shaft_length. The pose X_ST is that of the tool tip
/// frame T in the tissue frame S (origin = tip point, z_T = direction of insertion).
class ToolCapsule {
 public:
  /// @param radius capsule radius [m], finite and > 0
  /// @param shaft_length length of the axis segment behind the tip [m], finite and >= 0
  ///        (0 gives a sphere at the tip)
  /// @throws std::invalid_argument naming "tool.radius" or "tool.shaft_length"
  ToolCapsule(double radius, double shaft_length);

  /// Sets the pose X_ST of the tool tip frame T in the tissue frame S. Returns false (pose kept)
  /// if X_ST contains NaN/Inf. Never throws, allocation-free.
  bool setPose(const Eigen::Isometry3d& X_ST);

  const Eigen::Isometry3d& pose() const { return X_ST_; }  ///< X_ST
  double radius() const { return radius_; }                ///< [m]
  double shaftLength() const { return shaft_length_; }     ///< [m]
  /// Tip point p_ST [m], in S: the distal end of the axis segment (centre of the tip hemisphere).
  Eigen::Vector3d tip() const { return X_ST_.translation(); }
  /// Proximal end of the axis segment p_SE = X_ST (0, 0, -shaft_length) [m], in S.
  Eigen::Vector3d shaftEnd() const;
  /// Axis-aligned bounding box of the capsule inflated by margin [m], in S.
  Eigen::AlignedBox3d bounds(double margin) const;

 private:
  double radius_;
  double shaft_length_;
  Eigen::Isometry3d X_ST_ = Eigen::Isometry3d::Identity();
};

}  // namespace surgical_sim::core
