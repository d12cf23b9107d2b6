#pragma once

#include <vector>

#include "surgical_sim/core/haptics/passivity_controller.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

/// The H1 stiff-wall scenario: a 1-D virtual wall at x = 0 (free for x < 0, penetration x > 0),
/// rendered by a sampled-data device (zero-order hold at rate_hz, wall force -k_w x from the
/// sampled position, velocity from the backward difference of sampled positions, as a device
/// with encoders does) against a continuous mass-spring-damper "hand" that pulls the tool toward
/// hand_setpoint. Defaults are the H1 case (BENCHMARKS.md); all validated.
struct StiffWallSettings {
  double wall_stiffness = 5000.0;   ///< k_w [N/m], > 0
  double rate_hz = 1000.0;          ///< device loop rate [Hz], > 0
  double hand_mass = 0.2;           ///< hand + tool + reflected device mass [kg], > 0
  double hand_stiffness = 200.0;    ///< hand grip stiffness about the set point [N/m], >= 0
  double hand_damping = 0.5;        ///< hand damping [N s/m], >= 0 (below k_w T / 2: active wall)
  double hand_setpoint = 0.005;     ///< where the hand pulls the tool [m] (inside the wall)
  double initial_position = -0.01;  ///< tool position at t = 0 [m]
  double initial_velocity = 0.1;    ///< tool velocity at t = 0 [m/s], toward the wall
  double duration = 3.0;            ///< simulated time [s], > 0
  int substeps = 20;                ///< hand-dynamics RK4 substeps per device tick [-], >= 1
  bool passivity = false;           ///< apply the PassivityController
  PassivityControllerSettings passivity_settings;  ///< used when passivity is true
};

/// @throws std::invalid_argument naming "stiff_wall.<field>" with unit and range.
void validateStiffWallSettings(const StiffWallSettings& settings);

/// One device tick of the stiff-wall simulation.
struct StiffWallSample {
  double time;               ///< tick time [s]
  double position;           ///< sampled tool position [m]
  double velocity;           ///< true tool velocity at the tick [m/s]
  double force;              ///< force rendered on the tool during the tick [N]
  double observer_energy;    ///< passivity-observer energy E_obs [J] (computed in both modes)
  double mechanical_energy;  ///< hand kinetic + hand spring + ideal wall potential [J]
  double hand_energy;        ///< hand kinetic + hand spring (operator side only) [J]
};

/// Energy history of a stiff-wall run.
struct StiffWallResult {
  std::vector<StiffWallSample> history;  ///< one sample per device tick
  double initial_energy = 0.0;           ///< mechanical energy at t = 0 [J]
  double max_energy = 0.0;               ///< max mechanical energy over the run [J]
  double max_hand_energy = 0.0;          ///< max hand energy over the run [J]
  double late_max_energy = 0.0;          ///< max mechanical energy over the last third [J]
  double max_penetration = 0.0;          ///< max sampled penetration [m]
  double dissipated_energy = 0.0;        ///< energy removed by the passivity controller [J]
};

/// Runs the stiff-wall scenario deterministically (no clock, no randomness).
/// The continuous system (ideal wall, damped hand) can only lose energy; any growth of the
/// mechanical energy is energy injected by the sampled wall. Energy balance of the hand:
/// hand_energy(n) = hand_energy(0) - hand damping losses - observer_energy(n), so a passive
/// device (observer_energy >= 0) cannot raise the hand energy above its initial value.
/// @throws std::invalid_argument if the settings are invalid.
StiffWallResult simulateStiffWall(const StiffWallSettings& settings);

}  // namespace surgical_sim::bench
