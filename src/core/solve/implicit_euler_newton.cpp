#include "surgical_sim/core/solve/implicit_euler_newton.h"

#include <cmath>

#include "surgical_sim/core/solve/dirichlet_projection.h"
#include "surgical_sim/core/solve/mechanical_energy.h"

namespace surgical_sim::core {

ImplicitEulerNewton::ImplicitEulerNewton(const IntegratorSettings& settings,
                                         std::unique_ptr<LinearSolver> solver)
    : NewtonIntegratorBase(settings, std::move(solver), "implicit_euler_newton") {}

void ImplicitEulerNewton::patternAdopted() { damping_stiffness_ = stiffness_; }

void ImplicitEulerNewton::resizeNewtonWorkspace(Eigen::Index size) {
  for (Eigen::VectorXd* v : {&x_hat_, &force_, &offset_, &damping_product_}) v->setZero(size);
}

void ImplicitEulerNewton::applyFrozenDamping(const DynamicsProblem& problem,
                                             const Eigen::VectorXd& x) {
  const double alpha = problem.damping.mass_coefficient;
  const double beta = problem.damping.stiffness_coefficient;
  offset_ = x - x0_;
  if (beta > 0.0) {
    damping_product_.noalias() = damping_stiffness_ * offset_;
    damping_product_ *= beta;
  } else {
    damping_product_.setZero();
  }
  if (alpha > 0.0) {
    damping_product_.array() += alpha * problem.model->lumpedMass().array() * offset_.array();
  }
}

double ImplicitEulerNewton::computeResidual(const DynamicsProblem& problem,
                                            const Eigen::VectorXd& x, double* scale) {
  const Eigen::VectorXd& mass = problem.model->lumpedMass();
  force_ = problem.external_force;
  problem.model->addInternalForce(x, force_);
  const double dt2 = dt_ * dt_;
  residual_ = mass.cwiseProduct(x - x_hat_);
  double terms = residual_.norm() + mass.cwiseProduct(x).norm() + dt2 * stiffness_round_off_ +
                 dt2 * (force_.norm() + 2.0 * problem.external_force.norm());
  residual_.noalias() -= dt2 * force_;
  if (problem.damping.active()) {
    applyFrozenDamping(problem, x);
    residual_.noalias() += dt_ * damping_product_;
    terms += dt_ * damping_product_.norm();
  }
  zeroDirichletEntries(problem.dirichlet.dofs, residual_);
  *scale = terms;
  return residual_.norm();
}

double ImplicitEulerNewton::merit(const DynamicsProblem& problem, const Eigen::VectorXd& x,
                                  double* scale) {
  const Eigen::VectorXd& mass = problem.model->lumpedMass();
  const double inertia = 0.5 * (mass.array() * (x - x_hat_).array().square()).sum();
  const double elastic = dt_ * dt_ * problem.model->energy(x);
  const double external = -dt_ * dt_ * problem.external_force.dot(x - x0_);
  double damping = 0.0;
  if (problem.damping.active()) {
    applyFrozenDamping(problem, x);
    damping = 0.5 * dt_ * offset_.dot(damping_product_);
  }
  *scale = std::abs(inertia) + std::abs(elastic) + std::abs(external) + std::abs(damping);
  return inertia + elastic + external + damping;
}

void ImplicitEulerNewton::assembleSystem() {
  system_.assemble(model_->lumpedMass(), 1.0 + dt_ * damping_.mass_coefficient, stiffness_,
                   dt_ * dt_);
  if (damping_.stiffness_coefficient > 0.0) {
    system_.addStiffness(damping_stiffness_, dt_ * damping_.stiffness_coefficient);
  }
}

StepReport ImplicitEulerNewton::step(const DynamicsProblem& problem, double dt,
                                     SimulationState& state) {
  StepReport report;
  if (!beginStep(problem, dt, true, state)) return failedStart(report);
  const DirichletBc& bc = problem.dirichlet;
  dt_ = dt;
  damping_ = problem.damping;
  x_hat_ = x0_ + dt * v0_;
  state.x = x_hat_;
  for (size_t k = 0; k < bc.dofs.size(); ++k) {
    state.x[bc.dofs[k]] = bc.positions[static_cast<Eigen::Index>(k)];
  }
  if (damping_.stiffness_coefficient > 0.0) {
    model_->assembleStiffness(x0_, TangentMode::ProjectedSpd, damping_stiffness_);
  }

  report.status = solveNewton(problem, state.x, report);
  if (report.status == StepStatus::SolverFailed || report.status == StepStatus::NonFinite) {
    return restoreState(state, report.status, report);
  }
  state.v = (state.x - x0_) / dt;
  const double energy = mechanicalEnergy(*model_, state.x, state.v, problem.external_force);
  if (!state.x.allFinite() || !state.v.allFinite() || !std::isfinite(energy)) {
    return restoreState(state, StepStatus::NonFinite, report);
  }
  state.time += dt;
  compliance_x_ = state.x;
  compliance_.markStale(dt * dt);
  report.energy = energy;
  return report;
}

}  // namespace surgical_sim::core
