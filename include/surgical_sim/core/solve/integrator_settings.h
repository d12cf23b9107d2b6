#pragma once

namespace surgical_sim::core {

/// Settings of every integrator, as read from the configuration; each integrator uses its part.
/// Numerical, not physical: the defaults are documented choices.
struct IntegratorSettings {
  /// implicit_euler_newton, quasi_static: Newton iterations per solve [-], >= 1.
  int max_iterations = 20;
  /// implicit_euler_newton, quasi_static: converged when |r| <= tol |r_0| (r: residual force,
  /// free DOFs; r_0 at the start of the solve) [-], in (0, 1).
  double relative_tolerance = 1e-8;
  /// implicit_euler_newton, quasi_static: Armijo backtracking halvings per iteration [-], [0, 60].
  int max_line_search_halvings = 30;
  /// symplectic_euler: BlowUp when the total energy exceeds the energy budget (initial energy +
  /// energy supplied by prescribed motion and load changes) by more than this ratio times the
  /// largest energy scale seen so far [-], > 0.
  double blow_up_energy_ratio = 1.0;
  /// quasi_static: after a failed full-load solve, retry with 2, 4, ... 2^max_load_step_levels
  /// load increments [-], in [0, 16].
  int max_load_step_levels = 4;
};

/// @throws std::invalid_argument naming the out-of-range parameter with its range:
///         "integrator.max_iterations", "integrator.relative_tolerance",
///         "integrator.max_line_search_halvings", "integrator.blow_up_energy_ratio" or
///         "integrator.max_load_step_levels".
void validateIntegratorSettings(const IntegratorSettings& settings);

}  // namespace surgical_sim::core
