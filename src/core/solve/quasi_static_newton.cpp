#include "surgical_sim/core/solve/quasi_static_newton.h"

#include <algorithm>
#include <cmath>

#include "surgical_sim/core/solve/dirichlet_projection.h"
#include "surgical_sim/core/solve/mechanical_energy.h"

namespace surgical_sim::core {

QuasiStaticNewton::QuasiStaticNewton(const IntegratorSettings& settings,
                                     std::unique_ptr<LinearSolver> linear_solver)
    : NewtonIntegratorBase(settings, std::move(linear_solver), "quasi_static") {}

void QuasiStaticNewton::resizeNewtonWorkspace(Eigen::Index size) {
  for (Eigen::VectorXd* v : {&previous_load_, &load_, &targets_, &internal_}) v->setZero(size);
}

double QuasiStaticNewton::computeResidual(const DynamicsProblem& problem, const Eigen::VectorXd& x,
                                          double* scale) {
  internal_.setZero();
  problem.model->addInternalForce(x, internal_);
  residual_ = -(internal_ + load_);
  zeroDirichletEntries(problem.dirichlet.dofs, residual_);
  *scale = internal_.norm() + load_.norm() + stiffness_round_off_;
  return residual_.norm();
}

double QuasiStaticNewton::merit(const DynamicsProblem& problem, const Eigen::VectorXd& x,
                                double* scale) {
  const double elastic = problem.model->energy(x);
  const double external = -load_.dot(x - x0_);
  *scale = std::abs(elastic) + std::abs(external);
  return elastic + external;
}

void QuasiStaticNewton::assembleSystem() {
  system_.assemble(model_->lumpedMass(), 0.0, stiffness_, 1.0);
}

StepStatus QuasiStaticNewton::solveIncrement(const DynamicsProblem& problem, Eigen::VectorXd& x,
                                             StepReport& report) {
  for (const int d : problem.dirichlet.dofs) x[d] = targets_[d];
  const double largest_residual = report.residual;
  const StepStatus status = solveNewton(problem, x, report);
  report.residual = std::max(largest_residual, report.residual);
  return status;
}

StepReport QuasiStaticNewton::step(const DynamicsProblem& problem, double dt,
                                   SimulationState& state) {
  StepReport report;
  if (!beginStep(problem, dt, false, state)) return failedStart(report);
  const DirichletBc& bc = problem.dirichlet;

  StepStatus status = StepStatus::Ok;
  for (int level = 0; level <= settings_.max_load_step_levels; ++level) {
    const int increments = 1 << level;
    state.x = x0_;
    status = StepStatus::Ok;
    report.residual = 0.0;
    for (int i = 1; i <= increments; ++i) {
      const double fraction = static_cast<double>(i) / increments;
      load_ = previous_load_ + fraction * (problem.external_force - previous_load_);
      for (size_t k = 0; k < bc.dofs.size(); ++k) {
        const int d = bc.dofs[k];
        targets_[d] = x0_[d] + fraction * (bc.positions[static_cast<Eigen::Index>(k)] - x0_[d]);
      }
      const StepStatus increment = solveIncrement(problem, state.x, report);
      if (increment != StepStatus::Ok) status = increment;
      // On the finest level an unconverged (finite) increment does not stop the load path.
      if (status != StepStatus::Ok &&
          (level < settings_.max_load_step_levels || status != StepStatus::NotConverged)) {
        break;
      }
    }
    if (status == StepStatus::Ok) break;
  }

  const bool usable = status == StepStatus::Ok || status == StepStatus::NotConverged;
  if (!usable || !state.x.allFinite()) {
    return restoreState(state, usable ? StepStatus::NonFinite : status, report);
  }
  state.v.setZero();
  const double energy = mechanicalEnergy(*model_, state.x, state.v, problem.external_force);
  if (!std::isfinite(energy)) return restoreState(state, StepStatus::NonFinite, report);
  if (status == StepStatus::Ok) previous_load_ = problem.external_force;
  state.time += dt;
  compliance_x_ = state.x;
  compliance_.markStale(1.0);
  report.status = status;
  report.energy = energy;
  return report;
}

}  // namespace surgical_sim::core
