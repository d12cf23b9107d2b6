#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "surgical_sim/core/solve/integrator.h"

namespace surgical_sim::core {

/// Explicit symplectic (semi-implicit) Euler:
///   v <- v + dt M^-1 (f_int(x) + f_ext - C v),  x <- x + dt v,
/// with C v = alpha M v + beta K(x) v (K applied matrix-free, ProjectedSpd; only the active
/// damping terms are evaluated). Dirichlet DOFs: x_d <- target, v_d <- (target - x_d) / dt.
///
/// Stability needs dt < 2 / omega_max. Blow-up detection: non-finite values -> NonFinite;
/// total energy (kinetic + elastic - f_ext . x) above the energy budget by more than
/// blow_up_energy_ratio x the largest energy scale seen (kinetic + elastic + |f_ext| L, L the
/// rest bounding-box diagonal) -> BlowUp. Both restore the pre-step state. The budget is the
/// energy at the first step (re-based when the state was changed outside the integrator) plus the
/// energy supplied by the prescribed motion and by load changes.
class SymplecticEuler final : public Integrator {
 public:
  /// @param blow_up_energy_ratio see IntegratorSettings::blow_up_energy_ratio [-], > 0
  /// @throws std::invalid_argument naming "integrator.blow_up_energy_ratio"
  explicit SymplecticEuler(double blow_up_energy_ratio);

  /// Returns "symplectic_euler".
  std::string name() const override;
  /// One explicit step of dt [s] (> 0). Never throws; an inconsistent problem or dt returns
  /// SolverFailed with the state untouched.
  StepReport step(const DynamicsProblem& problem, double dt, SimulationState& state) override;
  /// Forgets buffers and the energy reference (the next step re-initializes them).
  void reset() override;
  /// dx = dt^2 M^-1 f (the explicit step's exact response), 0 on the last step's Dirichlet DOFs.
  bool applyStepCompliance(const Eigen::VectorXd& f, Eigen::VectorXd& dx) override;

 private:
  void setUp(const TissueModel& model);

  double blow_up_energy_ratio_;
  const TissueModel* model_ = nullptr;
  Eigen::VectorXd x0_, v0_, force_, damping_force_, previous_external_force_, split_;
  Eigen::VectorXd last_x_, last_v_;     ///< state after the last successful step
  double characteristic_length_ = 0.0;  ///< rest bounding-box diagonal [m]
  double energy_budget_ = 0.0;          ///< upper bound of the total energy [J]
  double energy_scale_ = 0.0;           ///< largest energy magnitude seen [J]
  bool energy_initialized_ = false;
  std::vector<std::uint8_t> mask_;  ///< Dirichlet mask of the last step, size 3n
  double last_dt_ = 0.0;            ///< dt of the last successful step [s]
  bool compliance_ready_ = false;   ///< a step succeeded since setUp / reset
};

}  // namespace surgical_sim::core
