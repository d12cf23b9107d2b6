#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Settings of PassivityController (controller limits, documented defaults).
struct PassivityControllerSettings {
  /// Largest adaptive damping the device may add [N s/m], > 0. With an effective moving mass m
  /// the discrete damper stays stable for max_damping < 2 m / dt (0.2 kg at 1 kHz: 400 N s/m).
  double max_damping = 100.0;
  /// Below this tip speed no damping is added (alpha would be ill-conditioned) [m/s], >= 0.
  double min_speed = 1e-4;
  /// false: observer only (E_obs is reported, the force passes unchanged).
  bool control_enabled = true;
};

/// @throws std::invalid_argument naming "haptics.passivity.max_damping" or
/// "haptics.passivity.min_speed".
void validatePassivityControllerSettings(const PassivityControllerSettings& settings);

/// Time-domain passivity observer / controller (Hannaford & Ryu 2002) for the impedance-type
/// one-port "device + virtual environment" seen by the operator.
///
/// Sign convention: f is the force the device applies to the operator's tool [N], v the tool-tip
/// velocity [m/s]; the power flowing from the operator into the device is P = -f . v, and the
/// port is passive while the observed energy E_obs >= 0.
///
/// Sampled-data observer: the force output at tick n-1 is held until tick n, while the tool
/// moves by v(n) dt, with v(n) = (x(n) - x(n-1)) / dt the backward-difference velocity. The
/// exact work of that interval is paired accordingly:
///   E_obs(n) = E_obs(n-1) - f_out(n-1) . v(n) dt   [J].
/// (Pairing f(n) with v(n) instead would hide the energy a zero-order-hold wall injects: for a
/// spring k it sums k x(n) (x(n) - x(n-1)) >= the stored energy, i.e. it always looks passive.)
/// When E_obs(n) < 0 the controller outputs f_out(n) = f(n) - alpha v(n) with
///   alpha = -E_obs(n) / (v(n) . v(n) dt)   (capped at max_damping),
/// which dissipates the deficit over the next interval if the velocity stays close to v(n); the
/// dissipation actually achieved shows up in E_obs(n+1). Fixed-size, allocation-free, never
/// throws.
class PassivityController {
 public:
  /// @throws std::invalid_argument if the settings are invalid.
  explicit PassivityController(const PassivityControllerSettings& settings);

  /// Observed energy to zero.
  void reset() noexcept;

  /// Observes one sample and returns the force to hold until the next tick, f - alpha v [N]
  /// (3x1). force_W: force the device would render on the operator [N]; v_W: tool-tip velocity
  /// over the last interval [m/s]; dt: interval [s] > 0; all in one frame. Non-finite inputs
  /// return zero force (which is then the held force) and leave E_obs unchanged.
  Eigen::Vector3d step(const Eigen::Vector3d& force_W, const Eigen::Vector3d& v_W,
                       double dt) noexcept;

  /// Tells the observer that the actuators rendered force_W instead of the last step() output
  /// (e.g. after effort saturation); this is the force held until the next tick [N] (3x1).
  void setHeldForce(const Eigen::Vector3d& force_W) noexcept;

  /// Observed energy E_obs after the last step [J] (measured work up to this tick).
  double observedEnergy() const noexcept { return energy_; }
  /// Damping alpha applied at the last step [N s/m].
  double damping() const noexcept { return damping_; }
  /// Energy the controller has scheduled for dissipation since reset, sum alpha v.v dt [J], >= 0.
  double dissipatedEnergy() const noexcept { return dissipated_; }

 private:
  PassivityControllerSettings settings_;
  double energy_ = 0.0;
  double damping_ = 0.0;
  double dissipated_ = 0.0;
  Eigen::Vector3d held_force_ = Eigen::Vector3d::Zero();
};

}  // namespace surgical_sim::core
