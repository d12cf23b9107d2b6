#pragma once

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "surgical_sim/core/haptics/local_contact_model.h"
#include "surgical_sim/core/haptics/passivity_controller.h"
#include "surgical_sim/core/haptics/trocar_chain.h"
#include "surgical_sim/core/haptics/trocar_device.h"
#include "surgical_sim/core/haptics/trocar_kinematics.h"
#include "surgical_sim/core/haptics/virtual_coupling.h"

namespace surgical_sim::core {

/// Everything the per-tick force rendering needs.
struct HapticRendererConfig {
  TrocarChain chain;                      ///< joint chain fulcrum -> tool tip (from the URDF)
  TrocarDeviceConfig device;              ///< drives, limits, encoders
  LocalContactSettings contact;           ///< staleness handling
  VirtualCouplingSettings coupling;       ///< proxy spring-damper (physical: no defaults)
  PassivityControllerSettings passivity;  ///< time-domain passivity control
  /// Pose of the trocar frame F (fulcrum) in the world frame W (tf world -> trocar_<i>).
  Eigen::Isometry3d X_WF = Eigen::Isometry3d::Identity();
  double rate_hz = 1000.0;  ///< loop rate [Hz], in [100, 20000]
};

/// @throws std::invalid_argument naming the offending parameter (see the member validators and
/// "haptics.rate_hz", "haptics.X_WF").
void validateHapticRendererConfig(const HapticRendererConfig& config);

/// Output of one rendering tick.
struct HapticOutput {
  std::uint64_t tick = 0;  ///< tick counter since construction/reset
  double time = 0.0;       ///< tick time [s] (the loop's clock)
  TrocarJointVector q_measured = TrocarJointVector::Zero();  ///< encoder reading [rad, m]
  bool joints_clamped = false;  ///< the command was outside the joint limits (or non-finite)
  Eigen::Isometry3d X_WT = Eigen::Isometry3d::Identity();  ///< tool-tip pose in W
  Eigen::Vector3d v_WT = Eigen::Vector3d::Zero();  ///< tip velocity, backward difference [m/s], W
  Eigen::Vector3d p_WP = Eigen::Vector3d::Zero();  ///< coupling proxy position [m], W
  Eigen::Vector3d f_contact_W = Eigen::Vector3d::Zero();  ///< contact model at the proxy [N], W
  /// Force actually rendered on the tool at its tip (after coupling, passivity, saturation) [N], W.
  Eigen::Vector3d f_rendered_W = Eigen::Vector3d::Zero();
  TrocarJointVector effort = TrocarJointVector::Zero();        ///< saturated joint efforts [N m, N]
  TrocarJointVector motor_torque = TrocarJointVector::Zero();  ///< motor torques [N m]
  EffortSaturation saturation;                                 ///< saturation report
  ContactStatus contact_status = ContactStatus::NoModel;
  double contact_age = 0.0;        ///< age of the contact model [s]
  double passivity_damping = 0.0;  ///< adaptive damping applied this tick [N s/m]
  double observer_energy = 0.0;    ///< passivity-observer energy [J]
};

/// The per-tick force-rendering pipeline of the active trocar (no thread, no clock): encoder
/// quantization -> FK -> local contact model at the proxy -> virtual coupling -> passivity
/// controller -> tau = J^T w -> direction-preserving saturation. The contact force acts at the
/// tool tip (no moment). update() allocates nothing and never throws; HapticLoop calls it at
/// rate_hz, benchmarks and tests call it directly.
class HapticRenderer {
 public:
  /// @throws std::invalid_argument if the configuration is invalid.
  explicit HapticRenderer(const HapticRendererConfig& config);

  const HapticRendererConfig& config() const { return config_; }
  const TrocarKinematics& kinematics() const { return kinematics_; }
  const TrocarDevice& device() const { return device_; }
  /// Mutable device, for set-up-time changes (e.g. setPitchYawLimits) outside update().
  TrocarDevice& device() { return device_; }

  /// Replaces the contact model (stamp on the clock passed to update()).
  void setContactSample(const LocalContactSample& sample) noexcept;
  /// Restarts velocity estimation, coupling proxy and passivity observer.
  void reset() noexcept;

  /// One tick at time now [s] with operator joint positions q_command (5x1). Returns the output
  /// of this tick (valid until the next call).
  const HapticOutput& update(const TrocarJointVector& q_command, double now) noexcept;

 private:
  HapticRendererConfig config_;
  TrocarKinematics kinematics_;
  TrocarDevice device_;
  LocalContactModel contact_;
  VirtualCoupling coupling_;
  PassivityController passivity_;
  double dt_;
  bool has_previous_ = false;
  Eigen::Vector3d p_WT_previous_ = Eigen::Vector3d::Zero();
  HapticOutput output_;
};

}  // namespace surgical_sim::core
