#include "surgical_sim/core/connective/coupled_solver.h"

#include <cmath>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/connective/rigid_node_tangent_system.h"

namespace surgical_sim::core {
CoupledSolver::CoupledSolver(ConnectiveCoupling& coupling, const CoupledSolverSettings& settings)
    : coupling_(coupling), settings_(settings) {
  requireNonNegative("CoupledSolverSettings.mass_damping", settings.mass_damping, "1/s");
  requireNonNegative("CoupledSolverSettings.stiffness_damping", settings.stiffness_damping, "s");
  requireInRange("CoupledSolverSettings.max_iterations", settings.max_iterations, 1, 1e6, "");
  requirePositive("CoupledSolverSettings.relative_tolerance", settings.relative_tolerance, "");
  requireInHalfOpenRange("CoupledSolverSettings.relative_tolerance", settings.relative_tolerance,
                         0.0, 1.0, "");
  requireInRange("CoupledSolverSettings.max_halvings", settings.max_halvings, 0, 1e3, "");
}

bool CoupledSolver::factorize(double mass_coefficient, double stiffness_coefficient) {
  if (!analysed_) {
    system_ = coupling_.stiffness();
    solver_.analyzePattern(system_);
    analysed_ = true;
  }
  const std::vector<int>& diagonal = coupling_.rotationDiagonal();
  double scale = 0.0;
  auto build = [&]() {
    system_.coeffs() = stiffness_coefficient * coupling_.stiffness().coeffs();
    if (mass_coefficient != 0.0) system_.coeffs() += mass_coefficient * coupling_.mass().coeffs();
  };
  build();
  for (const int k : diagonal) scale += std::abs(system_.valuePtr()[k]);
  if (!diagonal.empty()) scale /= static_cast<double>(diagonal.size());
  if (mass_coefficient != 0.0 && solver_.factorize(system_)) return true;
  for (const double shift : kRotationShifts) {
    build();
    for (const int k : diagonal) system_.valuePtr()[k] += shift * scale;
    if (solver_.factorize(system_)) return true;
  }
  return false;
}

bool CoupledSolver::factorizeAssembled(const CoupledState& state, const CoupledLoads& loads,
                                       double mass_coefficient, double stiffness_coefficient,
                                       StepPhaseTimes& phases) {
  material_only_ = false;
  if (timed(phases.factorization,
            [&]() { return factorize(mass_coefficient, stiffness_coefficient); }))
    return true;
  CouplingTangentOptions options;
  options.geometric = false;
  timed(phases.forces,
        [&]() { coupling_.assemble(state, loads, options, mass_coefficient != 0.0); });
  material_only_ = true;
  return timed(phases.factorization,
               [&]() { return factorize(mass_coefficient, stiffness_coefficient); });
}

LinearSolveReport CoupledSolver::solveSystem(const Eigen::VectorXd& b, StepPhaseTimes& phases) {
  if (du_.size() != b.size()) du_.setZero(b.size());
  LinearSolveReport report = timed(phases.linear_solve, [&]() { return solver_.solve(b, du_); });
  report.ok = report.ok && du_.allFinite();
  return report;
}

StepReport CoupledSolver::step(const CoupledLoads& loads, double dt, CoupledState& state) {
  requirePositive("CoupledSolver::step dt", dt, "s");
  StepReport report;
  coupling_.applyMapping(state);
  start_ = state;
  auto failed = [&](StepStatus status) {
    state = start_;
    report.status = status;
    return report;
  };
  const double alpha = settings_.mass_damping, beta = settings_.stiffness_damping;
  timed(report.phases.forces,
        [&]() { coupling_.assemble(state, loads, CouplingTangentOptions{}, true); });
  if (!factorizeAssembled(state, loads, 1.0 + dt * alpha, dt * beta + dt * dt, report.phases))
    return failed(StepStatus::SolverFailed);
  timed(report.phases.forces, [&]() {
    coupling_.gatherVelocity(state, velocity_);
    // b = h (f - alpha M u - (beta + h) K u).
    product_ = coupling_.stiffness() * velocity_;
    rhs_ = coupling_.force() - (beta + dt) * product_;
    if (alpha > 0.0) {
      product_ = coupling_.mass() * velocity_;
      rhs_ -= alpha * product_;
    }
    rhs_ *= dt;
  });
  const LinearSolveReport solve = solveSystem(rhs_, report.phases);
  if (!solve.ok) return failed(StepStatus::SolverFailed);
  velocity_ += du_;
  coupling_.scatterVelocity(velocity_, state);
  coupling_.applyIncrement(velocity_, dt, state);
  state.time += dt;
  report.newton_iterations = 1;
  report.linear_iterations = 1;
  report.residual = solve.relative_residual;
  product_ = coupling_.mass() * velocity_;
  report.energy = 0.5 * velocity_.dot(product_) + coupling_.potentialEnergy(state, loads);
  if (!std::isfinite(report.energy)) return failed(StepStatus::NonFinite);
  return report;
}

StepReport CoupledSolver::solveStatic(const CoupledLoads& loads, CoupledState& state) {
  StepReport report;
  coupling_.applyMapping(state);
  for (Eigen::VectorXd& v : state.organ_velocities) v.setZero();
  for (Eigen::VectorXd& v : state.layer_velocities) v.setZero();
  start_ = state;
  double energy = coupling_.potentialEnergy(state, loads);
  report.status = StepStatus::NotConverged;
  for (int iteration = 0; iteration < settings_.max_iterations; ++iteration) {
    timed(report.phases.forces,
          [&]() { coupling_.assemble(state, loads, CouplingTangentOptions{}, false); });
    const Eigen::VectorXd& f = coupling_.force();
    report.residual = coupling_.forceScale() > 0.0 ? f.norm() / coupling_.forceScale() : 0.0;
    if (!std::isfinite(report.residual)) {
      state = start_;
      report.status = StepStatus::NonFinite;
      return report;
    }
    if (report.residual <= settings_.relative_tolerance) {
      report.status = StepStatus::Ok;
      break;
    }
    if (!factorizeAssembled(state, loads, 0.0, 1.0, report.phases) ||
        !solveSystem(f, report.phases).ok) {
      state = start_;
      report.status = StepStatus::SolverFailed;
      return report;
    }
    ++report.newton_iterations;
    ++report.linear_iterations;
    const double slope = f.dot(du_);  // -dPi/ds at s = 0
    double step = 1.0;
    bool accepted = false;
    for (int halving = 0; halving <= settings_.max_halvings; ++halving, step *= 0.5) {
      trial_ = state;
      coupling_.applyIncrement(du_, step, trial_);
      const double trial_energy = coupling_.potentialEnergy(trial_, loads);
      // Armijo, with a round-off allowance for steps whose decrease is below it.
      if (trial_energy <= energy - 1e-4 * step * slope + 1e-12 * std::abs(energy)) {
        state = trial_;
        energy = trial_energy;
        accepted = true;
        break;
      }
    }
    if (!accepted) break;
  }
  report.energy = energy;
  return report;
}

}  // namespace surgical_sim::core
