#pragma once

#include <Eigen/Core>
#include <limits>

namespace surgical_sim::core {

/// Gains of VirtualCoupling. Physical parameters: no defaults (NaN fails validation).
struct VirtualCouplingSettings {
  double stiffness = std::numeric_limits<double>::quiet_NaN();  ///< coupling spring k [N/m], > 0
  double damping = std::numeric_limits<double>::quiet_NaN();    ///< coupling damper b [N s/m], >= 0
};

/// @throws std::invalid_argument naming "haptics.coupling.stiffness" or "haptics.coupling.damping".
void validateVirtualCouplingSettings(const VirtualCouplingSettings& settings);

/// Spring-damper between the device tool tip (position x_d, velocity v_d) and a massless proxy
/// x_p that touches the environment (Colgate's virtual coupling). Each step solves the proxy's
/// equilibrium implicitly (backward Euler for the proxy velocity v_p = (x_p - x_p_prev) / dt):
///
///   k (x_d - x_p) + b (v_d - v_p) + f_env(x_p) = 0,   f_env(x) = f_c + K_c (x - p_c),
///
/// and returns the force on the device, f_d = -(k (x_d - x_p) + b (v_d - v_p)) = f_env(x_p). The
/// rendered stiffness is the series combination of k and the environment, so k bounds what the
/// device has to render. If (k + b/dt) I - K_c is singular the stiffness term is dropped for that
/// step. All vectors are 3x1 in the world frame W. step() allocates nothing and never throws.
class VirtualCoupling {
 public:
  /// @throws std::invalid_argument if the settings are invalid.
  explicit VirtualCoupling(const VirtualCouplingSettings& settings);

  const VirtualCouplingSettings& settings() const { return settings_; }

  /// Puts the proxy at rest on the device tip p_WT [m].
  void reset(const Eigen::Vector3d& p_WT) noexcept;

  /// One coupling step of dt [s] (> 0). p_WT [m], v_WT [m/s]: device tip; f_c_W [N]: environment
  /// force at p_c_W [m]; K_c_W [N/m] (3x3): environment stiffness. Returns the force on the device
  /// [N], W. Non-finite inputs return zero and leave the proxy unchanged.
  Eigen::Vector3d step(const Eigen::Vector3d& p_WT, const Eigen::Vector3d& v_WT,
                       const Eigen::Vector3d& f_c_W, const Eigen::Matrix3d& K_c_W,
                       const Eigen::Vector3d& p_c_W, double dt) noexcept;

  /// Current proxy position [m], W.
  const Eigen::Vector3d& proxyPosition() const noexcept { return p_WP_; }

 private:
  VirtualCouplingSettings settings_;
  Eigen::Vector3d p_WP_ = Eigen::Vector3d::Zero();
};

}  // namespace surgical_sim::core
