#include "surgical_sim/bench/stiff_wall_simulation.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::bench {
namespace {

/// Hand acceleration [m/s^2] under a held device force [N].
double handAcceleration(const StiffWallSettings& s, double x, double v, double device_force) {
  return (s.hand_stiffness * (s.hand_setpoint - x) - s.hand_damping * v + device_force) /
         s.hand_mass;
}

double handEnergy(const StiffWallSettings& s, double x, double v) {
  const double stretch = x - s.hand_setpoint;
  return 0.5 * s.hand_mass * v * v + 0.5 * s.hand_stiffness * stretch * stretch;
}

double mechanicalEnergy(const StiffWallSettings& s, double x, double v) {
  const double penetration = std::max(0.0, x);
  return handEnergy(s, x, v) + 0.5 * s.wall_stiffness * penetration * penetration;
}

}  // namespace

void validateStiffWallSettings(const StiffWallSettings& s) {
  requirePositive("stiff_wall.wall_stiffness", s.wall_stiffness, "N/m");
  requirePositive("stiff_wall.rate_hz", s.rate_hz, "Hz");
  requirePositive("stiff_wall.hand_mass", s.hand_mass, "kg");
  requireNonNegative("stiff_wall.hand_stiffness", s.hand_stiffness, "N/m");
  requireNonNegative("stiff_wall.hand_damping", s.hand_damping, "N s/m");
  requireFinite("stiff_wall.hand_setpoint", s.hand_setpoint, "m");
  requireFinite("stiff_wall.initial_position", s.initial_position, "m");
  requireFinite("stiff_wall.initial_velocity", s.initial_velocity, "m/s");
  requirePositive("stiff_wall.duration", s.duration, "s");
  requireInRange("stiff_wall.substeps", s.substeps, 1, 10000, "");
  if (s.passivity) validatePassivityControllerSettings(s.passivity_settings);
}

StiffWallResult simulateStiffWall(const StiffWallSettings& s) {
  validateStiffWallSettings(s);
  const double T = 1.0 / s.rate_hz;
  const int ticks = static_cast<int>(std::ceil(s.duration * s.rate_hz));
  const double h = T / s.substeps;

  // Without control the observer still runs, so both modes report E_obs.
  PassivityControllerSettings pc_settings = s.passivity_settings;
  pc_settings.control_enabled = s.passivity;
  PassivityController controller(pc_settings);
  StiffWallResult result;
  result.history.reserve(ticks);
  result.initial_energy = mechanicalEnergy(s, s.initial_position, s.initial_velocity);
  result.max_energy = result.initial_energy;
  result.max_hand_energy = handEnergy(s, s.initial_position, s.initial_velocity);

  double x = s.initial_position, v = s.initial_velocity;
  double x_prev_sample = s.initial_position - s.initial_velocity * T;
  for (int n = 0; n < ticks; ++n) {
    // Sample, compute the held force.
    const double v_est = (x - x_prev_sample) / T;
    x_prev_sample = x;
    const double wall_force = -s.wall_stiffness * std::max(0.0, x);
    const double force = controller.step(Eigen::Vector3d(wall_force, 0.0, 0.0),
                                         Eigen::Vector3d(v_est, 0.0, 0.0), T)[0];
    const double observer_energy = controller.observedEnergy();
    const double energy = mechanicalEnergy(s, x, v);
    const double hand_energy = handEnergy(s, x, v);
    result.history.push_back({n * T, x, v, force, observer_energy, energy, hand_energy});
    result.max_energy = std::max(result.max_energy, energy);
    result.max_hand_energy = std::max(result.max_hand_energy, hand_energy);
    if (n >= 2 * ticks / 3) result.late_max_energy = std::max(result.late_max_energy, energy);
    result.max_penetration = std::max(result.max_penetration, x);

    // Continuous hand dynamics under the held force (RK4).
    for (int i = 0; i < s.substeps; ++i) {
      const double k1x = v, k1v = handAcceleration(s, x, v, force);
      const double k2x = v + 0.5 * h * k1v;
      const double k2v = handAcceleration(s, x + 0.5 * h * k1x, k2x, force);
      const double k3x = v + 0.5 * h * k2v;
      const double k3v = handAcceleration(s, x + 0.5 * h * k2x, k3x, force);
      const double k4x = v + h * k3v;
      const double k4v = handAcceleration(s, x + h * k3x, k4x, force);
      x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
      v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    }
  }
  result.dissipated_energy = controller.dissipatedEnergy();
  return result;
}

}  // namespace surgical_sim::bench
