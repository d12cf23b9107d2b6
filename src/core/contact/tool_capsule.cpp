#include "surgical_sim/core/contact/tool_capsule.h"

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

ToolCapsule::ToolCapsule(double radius, double shaft_length)
    : radius_(radius), shaft_length_(shaft_length) {
  requirePositive("tool.radius", radius, "m");
  requireNonNegative("tool.shaft_length", shaft_length, "m");
}

bool ToolCapsule::setPose(const Eigen::Isometry3d& X_ST) {
  if (!X_ST.matrix().allFinite()) return false;
  X_ST_ = X_ST;
  return true;
}

Eigen::Vector3d ToolCapsule::shaftEnd() const {
  return X_ST_ * Eigen::Vector3d(0.0, 0.0, -shaft_length_);
}

Eigen::AlignedBox3d ToolCapsule::bounds(double margin) const {
  const Eigen::Vector3d a = tip();
  const Eigen::Vector3d b = shaftEnd();
  const Eigen::Vector3d inflate = Eigen::Vector3d::Constant(radius_ + margin);
  return Eigen::AlignedBox3d(a.cwiseMin(b) - inflate, a.cwiseMax(b) + inflate);
}

}  // namespace surgical_sim::core
