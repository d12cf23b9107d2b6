#include "surgical_sim/core/solve/implicit_euler_linearized.h"

#include <cmath>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/solve/dirichlet_projection.h"
#include "surgical_sim/core/solve/mechanical_energy.h"

namespace surgical_sim::core {

ImplicitEulerLinearized::ImplicitEulerLinearized(std::unique_ptr<LinearSolver> linear_solver,
                                                 int max_halvings)
    : ImplicitIntegratorBase(std::move(linear_solver), "implicit_euler_linearized"),
      max_halvings_(max_halvings) {}

void ImplicitEulerLinearized::resizeWorkspace(Eigen::Index size) {
  for (Eigen::VectorXd* v : {&rhs_, &dv_, &product_, &start_, &direction_, &offset_}) {
    v->setZero(size);
  }
  end_force_.resize(0);
  end_stiffness_.resize(0, 0);
  forgetModelEvaluations();
}

void ImplicitEulerLinearized::forgetModelEvaluations() {
  last_x_.resize(0);
  end_valid_ = false;
  end_pattern_checked_ = false;
}

double ImplicitEulerLinearized::incrementalPotential(const DynamicsProblem& problem, double dt,
                                                     const Eigen::VectorXd& x,
                                                     double elastic_energy) {
  const Eigen::VectorXd& mass = problem.model->lumpedMass();
  const double alpha = problem.damping.mass_coefficient;
  const double beta = problem.damping.stiffness_coefficient;
  offset_ = x - x0_;  // x - x_n
  double phi = elastic_energy - problem.external_force.dot(x);
  phi += 0.5 * (mass.array() * (offset_ - dt * v0_).array().square()).sum() / (dt * dt);
  if (alpha > 0.0) phi += 0.5 * alpha * (mass.array() * offset_.array().square()).sum() / dt;
  if (beta > 0.0 && !offset_.isZero(0.0)) {
    product_.noalias() = stiffness_ * offset_;
    phi += 0.5 * beta * offset_.dot(product_) / dt;
  }
  return phi;
}

double ImplicitEulerLinearized::endForceStiffnessAndEnergy(const TissueModel& model,
                                                           const Eigen::VectorXd& x) {
  if (!end_pattern_checked_ && !samePattern(end_stiffness_, stiffness_))
    end_stiffness_ = stiffness_;
  end_pattern_checked_ = true;
  end_force_.setZero(x.size());
  return model.addInternalForceStiffnessAndEnergy(x, TangentMode::ProjectedSpd, end_force_,
                                                  end_stiffness_);
}

StepReport ImplicitEulerLinearized::step(const DynamicsProblem& problem, double dt,
                                         SimulationState& state) {
  StepReport report;
  if (!beginStep(problem, dt, true, state)) return failedStart(report);
  const TissueModel& model = *problem.model;
  const Eigen::VectorXd& mass = model.lumpedMass();
  const DirichletBc& bc = problem.dirichlet;
  const double alpha = problem.damping.mass_coefficient;
  const double beta = problem.damping.stiffness_coefficient;

  for (size_t k = 0; k < bc.dofs.size(); ++k) {
    const int d = bc.dofs[k];
    state.v[d] = (bc.positions[static_cast<Eigen::Index>(k)] - state.x[d]) / dt;
  }
  rhs_ = problem.external_force;
  StepPhaseTimes& phases = report.phases;
  // The force and stiffness evaluated with the last step's end energy are those at x when nothing
  // moved the state since; a step that starts where the last one ended predicts the same of the
  // next step and evaluates them with its end energy.
  const bool unchanged = last_x_.size() == state.x.size() && last_x_ == state.x;
  timed(phases.forces, [&] {
    if (end_valid_ && unchanged) {
      rhs_ += end_force_;
      stiffness_.swap(end_stiffness_);
    } else {
      model.addInternalForceAndStiffness(state.x, TangentMode::ProjectedSpd, rhs_, stiffness_);
    }
  });
  end_valid_ = false;
  if (alpha > 0.0) rhs_.array() -= alpha * mass.array() * state.v.array();
  product_.noalias() = stiffness_ * state.v;
  rhs_.noalias() -= (dt + beta) * product_;
  rhs_ *= dt;
  zeroDirichletEntries(bc.dofs, rhs_);
  timed(phases.assembly, [&] {
    system_.assemble(mass, 1.0 + dt * alpha, stiffness_, dt * dt + dt * beta);
    system_.projectDirichlet(mask_);
  });
  if (!rhs_.allFinite()) return restoreState(state, StepStatus::NonFinite, report);
  if (!timed(phases.factorization, [&] {
        solver_->setLinearizationState(model, state.x);
        return solver_->factorize(system_.matrix());
      }))
    return restoreState(state, StepStatus::SolverFailed, report);
  // Initial guess of an iterative solve: the previous step's velocity change (zero after set-up
  // or reset), which the smooth motion of a tissue keeps close to this step's.
  zeroDirichletEntries(bc.dofs, dv_);
  const LinearSolveReport solve =
      timed(phases.linear_solve, [&] { return solver_->solve(rhs_, dv_); });
  report.linear_iterations = solve.iterations;
  // An iterative solve stopped at its iteration cap is still a usable inexact Newton step (every
  // CG iterate reduces the energy-norm error; the energy safeguard below catches overshoot):
  // keep it and report NotConverged. Only non-finite results fail.
  if (!solve.ok) {
    if (!dv_.allFinite()) return restoreState(state, StepStatus::NonFinite, report);
    report.status = StepStatus::NotConverged;
  }

  // Start point: x_n with the Dirichlet DOFs at their targets; direction: the Newton step.
  start_ = x0_;
  for (size_t k = 0; k < bc.dofs.size(); ++k) {
    start_[bc.dofs[k]] = bc.positions[static_cast<Eigen::Index>(k)];
  }
  direction_ = x0_ + dt * (state.v + dv_) - start_;
  for (int d : bc.dofs) direction_[d] = 0.0;
  const double w_start = (last_x_.size() == start_.size() && last_x_ == start_)
                             ? last_elastic_energy_
                             : model.energy(start_);
  const double phi_start = incrementalPotential(problem, dt, start_, w_start);
  double step_length = 1.0;
  double w_new = 0.0;
  bool end_evaluated = false;
  for (int halving = 0;; ++halving) {
    state.x = start_ + step_length * direction_;
    end_evaluated = halving == 0 && unchanged;
    if (end_evaluated) {
      w_new = timed(phases.forces, [&] { return endForceStiffnessAndEnergy(model, state.x); });
    } else {
      w_new = model.energy(state.x);
    }
    const double phi = incrementalPotential(problem, dt, state.x, w_new);
    if (!std::isfinite(phi)) return restoreState(state, StepStatus::NonFinite, report);
    if (phi <= phi_start + 1e-12 * (std::abs(phi_start) + std::abs(phi))) break;
    if (halving >= max_halvings_) {
      report.status = StepStatus::NotConverged;
      break;
    }
    step_length *= 0.5;
  }
  state.v = (state.x - x0_) / dt;
  const double energy = kineticEnergy(mass, state.v) + w_new - problem.external_force.dot(state.x);
  if (!state.x.allFinite() || !state.v.allFinite() || !std::isfinite(energy)) {
    return restoreState(state, StepStatus::NonFinite, report);
  }
  last_x_ = state.x;
  last_elastic_energy_ = w_new;
  end_valid_ = end_evaluated;
  compliance_.markFactorized(dt * dt);
  state.time += dt;
  report.newton_iterations = 1;
  report.residual = solve.relative_residual;
  report.energy = energy;
  return report;
}

}  // namespace surgical_sim::core
