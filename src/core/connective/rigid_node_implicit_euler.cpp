#include "surgical_sim/core/connective/rigid_node_implicit_euler.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/solve/dirichlet_projection.h"

namespace surgical_sim::core {

void validateRigidNodeImplicitEulerSettings(const RigidNodeImplicitEulerSettings& settings) {
  const double int_max = std::numeric_limits<int>::max();
  requireInRange("refresh_interval", settings.refresh_interval, 1, int_max, "");
  requireInHalfOpenRange("relative_tolerance", settings.relative_tolerance,
                         std::numeric_limits<double>::min(), 1.0, "");
  requireInRange("max_pcg_iterations", settings.max_pcg_iterations, 1, int_max, "");
}

RigidNodeImplicitEuler::RigidNodeImplicitEuler(const RigidNodeImplicitEulerSettings& settings)
    : settings_(settings) {
  validateRigidNodeImplicitEulerSettings(settings);
}

StepReport RigidNodeImplicitEuler::step(const RigidNodeProblem& problem, double dt,
                                        RigidNodeState& state) {
  checkRigidNodeProblem(problem);
  requirePositive("RigidNodeImplicitEuler::step dt", dt, "s");
  const RigidNodeModel& model = *problem.model;
  if (state.configuration.numNodes() != model.numNodes() ||
      state.velocity.size() != model.numDofs()) {
    std::ostringstream msg;
    msg << "RigidNodeImplicitEuler::step: state of " << state.configuration.numNodes()
        << " rigid nodes and " << state.velocity.size() << " velocities for a model of "
        << model.numNodes() << " nodes (" << model.numDofs() << " velocities)";
    throw std::invalid_argument(msg.str());
  }
  StepReport report;
  start_ = state.configuration;
  start_velocity_ = state.velocity;
  auto fail = [&](StepStatus status) {
    state.configuration = start_;
    state.velocity = start_velocity_;
    report.status = status;
    return report;
  };
  zeroDirichletEntries(problem.fixed_dofs, state.velocity);
  const double alpha = problem.mass_damping, beta = problem.stiffness_damping;
  const double mass_coefficient = 1.0 + dt * alpha, stiffness_coefficient = dt * beta + dt * dt;
  // b = h (f - alpha M v - (beta + h) K v).
  auto assembleRhs = [&]() {
    product_ = system_.stiffness() * state.velocity;
    rhs_ = system_.totalForce() - (beta + dt) * product_;
    if (alpha > 0.0) {
      product_ = system_.mass() * state.velocity;
      rhs_ -= alpha * product_;
    }
    rhs_ *= dt;
    zeroDirichletEntries(problem.fixed_dofs, rhs_);
  };
  // Factorizes, then solves directly.
  auto solveDirectly = [&]() {
    LinearSolveReport solve;
    const StepPhaseTimes before = report.phases;
    if (!system_.assemble(problem, state.configuration, mass_coefficient, stiffness_coefficient))
      return solve;
    ++factorizations_;
    steps_since_factorization_ = 0;
    report.phases = system_.phases();
    report.phases.forces += before.forces;
    report.phases.assembly += before.assembly;
    report.phases.linear_solve += before.linear_solve;
    assembleRhs();
    solve = timed(report.phases.linear_solve, [&]() { return system_.solve(rhs_, dv_); });
    report.linear_iterations = 1;
    return solve;
  };
  LinearSolveReport solve;
  if (steps_since_factorization_ < settings_.refresh_interval &&
      system_.assembleKeepingFactor(problem, state.configuration, mass_coefficient,
                                    stiffness_coefficient)) {
    report.phases = system_.phases();
    assembleRhs();
    solve = timed(report.phases.linear_solve, [&]() {
      return system_.solveWithKeptFactor(rhs_, dv_, settings_.relative_tolerance,
                                         settings_.max_pcg_iterations);
    });
    report.linear_iterations = solve.iterations;
    if (!solve.ok || !(solve.relative_residual <= settings_.relative_tolerance))
      solve = solveDirectly();
  } else {
    solve = solveDirectly();
  }
  if (!solve.ok) return fail(StepStatus::SolverFailed);
  ++steps_since_factorization_;
  state.velocity += dv_;
  applyRigidNodeIncrement(state.velocity, dt, state.configuration);
  if (!state.velocity.allFinite()) return fail(StepStatus::NonFinite);
  state.time += dt;
  report.newton_iterations = 1;
  report.residual = solve.relative_residual;
  product_ = system_.mass() * state.velocity;
  report.energy = 0.5 * state.velocity.dot(product_) + model.energy(state.configuration) +
                  model.bodyForcePotential(state.configuration, problem.body_acceleration);
  return report;
}

}  // namespace surgical_sim::core
