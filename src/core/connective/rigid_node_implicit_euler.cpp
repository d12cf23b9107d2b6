#include "surgical_sim/core/connective/rigid_node_implicit_euler.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/solve/dirichlet_projection.h"

namespace surgical_sim::core {

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
  if (!system_.assemble(problem, state.configuration, 1.0 + dt * alpha, dt * beta + dt * dt))
    return fail(StepStatus::SolverFailed);
  // b = h (f - alpha M v - (beta + h) K v).
  product_ = system_.stiffness() * state.velocity;
  rhs_ = system_.totalForce() - (beta + dt) * product_;
  if (alpha > 0.0) {
    product_ = system_.mass() * state.velocity;
    rhs_ -= alpha * product_;
  }
  rhs_ *= dt;
  zeroDirichletEntries(problem.fixed_dofs, rhs_);
  report.phases = system_.phases();
  const LinearSolveReport solve =
      timed(report.phases.linear_solve, [&]() { return system_.solve(rhs_, dv_); });
  if (!solve.ok) return fail(StepStatus::SolverFailed);
  state.velocity += dv_;
  applyRigidNodeIncrement(state.velocity, dt, state.configuration);
  if (!state.velocity.allFinite()) return fail(StepStatus::NonFinite);
  state.time += dt;
  report.newton_iterations = 1;
  report.linear_iterations = 1;
  report.residual = solve.relative_residual;
  product_ = system_.mass() * state.velocity;
  report.energy = 0.5 * state.velocity.dot(product_) + model.energy(state.configuration) +
                  model.bodyForcePotential(state.configuration, problem.body_acceleration);
  return report;
}

}  // namespace surgical_sim::core
