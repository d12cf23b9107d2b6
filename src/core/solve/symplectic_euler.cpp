#include "surgical_sim/core/solve/symplectic_euler.h"

#include <algorithm>
#include <cmath>

#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/solve/dirichlet_projection.h"
#include "surgical_sim/core/solve/dynamics_problem_check.h"
#include "surgical_sim/core/solve/mechanical_energy.h"

namespace surgical_sim::core {

SymplecticEuler::SymplecticEuler(double blow_up_energy_ratio)
    : blow_up_energy_ratio_(blow_up_energy_ratio) {
  requirePositive("integrator.blow_up_energy_ratio", blow_up_energy_ratio, "");
}

std::string SymplecticEuler::name() const { return "symplectic_euler"; }

void SymplecticEuler::reset() {
  model_ = nullptr;
  energy_initialized_ = false;
  compliance_ready_ = false;
}

void SymplecticEuler::setUp(const TissueModel& model) {
  const Eigen::VectorXd& rest = model.restPositions();
  const Eigen::Index size = rest.size();
  model_ = &model;
  x0_.setZero(size);
  v0_.setZero(size);
  force_.setZero(size);
  damping_force_.setZero(size);
  previous_external_force_.setZero(size);
  split_.setZero(size);
  last_x_.setZero(size);
  last_v_.setZero(size);
  mask_.assign(static_cast<size_t>(size), 0);
  compliance_ready_ = false;
  energy_scale_ = 0.0;
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(0.0);
  Eigen::Vector3d upper = Eigen::Vector3d::Constant(0.0);
  for (Eigen::Index i = 0; i + 2 < size; i += 3) {
    const Eigen::Vector3d p = rest.segment<3>(i);
    lower = i == 0 ? p : lower.cwiseMin(p);
    upper = i == 0 ? p : upper.cwiseMax(p);
  }
  characteristic_length_ = (upper - lower).norm();
  energy_initialized_ = false;
}

StepReport SymplecticEuler::step(const DynamicsProblem& problem, double dt,
                                 SimulationState& state) {
  StepReport report;
  compliance_ready_ = false;
  if (findProblemError(problem, state) != nullptr || !std::isfinite(dt) || !(dt > 0.0)) {
    report.status = StepStatus::SolverFailed;
    return report;
  }
  const TissueModel& model = *problem.model;
  if (model_ != &model || x0_.size() != state.x.size()) setUp(model);
  markDirichletDofs(problem.dirichlet.dofs, mask_);
  const Eigen::VectorXd& mass = model.lumpedMass();
  const Eigen::VectorXd& f_ext = problem.external_force;
  const DirichletBc& bc = problem.dirichlet;
  const RayleighDamping& damping = problem.damping;

  if (!energy_initialized_ || state.x != last_x_ || state.v != last_v_) {
    // First step, or the state was changed outside the integrator: re-base the budget.
    energy_budget_ = mechanicalEnergy(model, state.x, state.v, f_ext);
    energy_scale_ = std::max(energy_scale_, kineticEnergy(mass, state.v) + model.energy(state.x) +
                                                f_ext.norm() * characteristic_length_);
    energy_initialized_ = true;
  } else {
    // The potential -f_ext . x shifts when the load changes between steps.
    energy_budget_ -= (f_ext - previous_external_force_).dot(state.x);
  }
  previous_external_force_ = f_ext;
  x0_ = state.x;
  v0_ = state.v;

  force_ = f_ext;
  model.addInternalForce(state.x, force_);
  if (damping.mass_coefficient > 0.0) {
    force_.array() -= damping.mass_coefficient * mass.array() * state.v.array();
  }
  if (damping.stiffness_coefficient > 0.0) {
    model.applyStiffness(state.x, TangentMode::ProjectedSpd, state.v, damping_force_);
    force_.noalias() -= damping.stiffness_coefficient * damping_force_;
  }

  // Energy supplied by the prescribed motion, split off as a first sub-step that moves only the
  // constrained DOFs: elastic + external potential + kinetic change.
  double injected = 0.0;
  if (!bc.dofs.empty()) {
    split_ = x0_;
    for (size_t k = 0; k < bc.dofs.size(); ++k) {
      const int d = bc.dofs[k];
      const double displacement = bc.positions[static_cast<Eigen::Index>(k)] - x0_[d];
      const double velocity = displacement / dt;
      split_[d] += displacement;
      injected +=
          -f_ext[d] * displacement + 0.5 * mass[d] * (velocity * velocity - v0_[d] * v0_[d]);
    }
    injected += model.energy(split_) - model.energy(x0_);
  }

  state.v.array() += dt * force_.array() / mass.array();
  for (size_t k = 0; k < bc.dofs.size(); ++k) {
    const int d = bc.dofs[k];
    state.v[d] = (bc.positions[static_cast<Eigen::Index>(k)] - x0_[d]) / dt;
  }
  state.x.noalias() += dt * state.v;
  for (size_t k = 0; k < bc.dofs.size(); ++k) {
    state.x[bc.dofs[k]] = bc.positions[static_cast<Eigen::Index>(k)];
  }

  const double kinetic = kineticEnergy(mass, state.v);
  const double elastic = model.energy(state.x);
  const double energy = kinetic + elastic - f_ext.dot(state.x);
  if (!state.x.allFinite() || !state.v.allFinite() || !std::isfinite(energy)) {
    state.x = x0_;
    state.v = v0_;
    report.status = StepStatus::NonFinite;
    return report;
  }
  const double budget = energy_budget_ + injected;
  if (energy > budget + blow_up_energy_ratio_ * energy_scale_) {
    state.x = x0_;
    state.v = v0_;
    report.status = StepStatus::BlowUp;
    return report;
  }
  energy_budget_ = budget;
  energy_scale_ =
      std::max(energy_scale_, kinetic + elastic + f_ext.norm() * characteristic_length_);
  last_x_ = state.x;
  last_v_ = state.v;
  state.time += dt;
  last_dt_ = dt;
  compliance_ready_ = true;
  report.energy = energy;
  return report;
}

bool SymplecticEuler::applyStepCompliance(const Eigen::VectorXd& f, Eigen::VectorXd& dx) {
  if (!compliance_ready_ || f.size() != x0_.size()) return false;
  dx.resize(f.size());
  dx.array() = (last_dt_ * last_dt_) * f.array() / model_->lumpedMass().array();
  for (Eigen::Index i = 0; i < dx.size(); ++i) {
    if (mask_[static_cast<size_t>(i)] != 0) dx[i] = 0.0;
  }
  return true;
}

}  // namespace surgical_sim::core
