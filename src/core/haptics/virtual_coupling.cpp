#include "surgical_sim/core/haptics/virtual_coupling.h"

#include <cmath>

#include <Eigen/LU>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

void validateVirtualCouplingSettings(const VirtualCouplingSettings& settings) {
  requirePositive("haptics.coupling.stiffness", settings.stiffness, "N/m");
  requireNonNegative("haptics.coupling.damping", settings.damping, "N s/m");
}

VirtualCoupling::VirtualCoupling(const VirtualCouplingSettings& settings) : settings_(settings) {
  validateVirtualCouplingSettings(settings_);
}

void VirtualCoupling::reset(const Eigen::Vector3d& p_WT) noexcept { p_WP_ = p_WT; }

Eigen::Vector3d VirtualCoupling::step(const Eigen::Vector3d& p_WT, const Eigen::Vector3d& v_WT,
                                      const Eigen::Vector3d& f_c_W, const Eigen::Matrix3d& K_c_W,
                                      const Eigen::Vector3d& p_c_W, double dt) noexcept {
  if (!(dt > 0.0) || !std::isfinite(dt) || !p_WT.allFinite() || !v_WT.allFinite() ||
      !f_c_W.allFinite() || !K_c_W.allFinite() || !p_c_W.allFinite()) {
    return Eigen::Vector3d::Zero();
  }
  const double k = settings_.stiffness;
  const double b_dt = settings_.damping / dt;
  const Eigen::Vector3d rhs_coupling = k * p_WT + settings_.damping * v_WT + b_dt * p_WP_;

  Eigen::Matrix3d A = (k + b_dt) * Eigen::Matrix3d::Identity() - K_c_W;
  Eigen::Matrix3d A_inv;
  bool invertible = false;
  A.computeInverseWithCheck(A_inv, invertible, 1e-12 * (k + b_dt));
  Eigen::Vector3d p_WP;
  if (invertible) {
    p_WP = A_inv * (rhs_coupling + f_c_W - K_c_W * p_c_W);
  } else {
    // Drop the stiffness: the environment force is held at f_c for this step.
    p_WP = (rhs_coupling + f_c_W) / (k + b_dt);
  }
  if (!p_WP.allFinite()) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d v_WP = (p_WP - p_WP_) / dt;
  p_WP_ = p_WP;
  return -(k * (p_WT - p_WP) + settings_.damping * (v_WT - v_WP));
}

}  // namespace surgical_sim::core
