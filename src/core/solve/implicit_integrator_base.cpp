#include "surgical_sim/core/solve/implicit_integrator_base.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/solve/dirichlet_projection.h"
#include "surgical_sim/core/solve/dynamics_problem_check.h"

namespace surgical_sim::core {

ImplicitIntegratorBase::ImplicitIntegratorBase(std::unique_ptr<LinearSolver> linear_solver,
                                               std::string name)
    : solver_(std::move(linear_solver)), name_(std::move(name)) {
  if (!solver_) throw std::invalid_argument("solver: " + name_ + " needs a linear solver (null)");
}

std::string ImplicitIntegratorBase::name() const { return name_; }

void ImplicitIntegratorBase::reset() {
  model_ = nullptr;
  compliance_.invalidate();
}

void ImplicitIntegratorBase::modelChanged() {
  compliance_.invalidate();
  forgetModelEvaluations();
  model_changed_ = true;
}

void ImplicitIntegratorBase::setUp(const TissueModel& model) {
  const Eigen::Index size = model.stiffnessPattern().rows();
  model_ = &model;
  adoptPattern(model, false);
  mask_.assign(static_cast<size_t>(size), 0);
  x0_.setZero(size);
  v0_.setZero(size);
  resizeWorkspace(size);
}

void ImplicitIntegratorBase::adoptPattern(const TissueModel& model, bool changed) {
  stiffness_ = model.stiffnessPattern();
  stiffness_.makeCompressed();
  system_.setPattern(stiffness_);
  if (changed) {
    solver_->analyzeChangedPattern(system_.matrix());
  } else {
    solver_->analyzePattern(system_.matrix());
  }
  patternAdopted();
}

bool ImplicitIntegratorBase::beginStep(const DynamicsProblem& problem, double dt,
                                       bool dt_must_be_positive, const SimulationState& state) {
  compliance_.invalidate();
  if (findProblemError(problem, state) != nullptr || !std::isfinite(dt) ||
      (dt_must_be_positive && !(dt > 0.0))) {
    return false;
  }
  const TissueModel& model = *problem.model;
  const Eigen::SparseMatrix<double>& pattern = model.stiffnessPattern();
  if (model_ != &model || pattern.rows() != stiffness_.rows()) {
    setUp(model);
  } else if (model_changed_) {
    if (!samePattern(pattern, stiffness_)) adoptPattern(model, true);
  } else if (!system_.matchesPattern(pattern)) {
    setUp(model);
  }
  model_changed_ = false;
  markDirichletDofs(problem.dirichlet.dofs, mask_);
  x0_ = state.x;
  v0_ = state.v;
  return true;
}

StepReport ImplicitIntegratorBase::failedStart(StepReport report) {
  report.status = StepStatus::SolverFailed;
  return report;
}

StepReport ImplicitIntegratorBase::restoreState(SimulationState& state, StepStatus status,
                                                StepReport report) const {
  state.x = x0_;
  state.v = v0_;
  report.status = status;
  return report;
}

bool ImplicitIntegratorBase::applyStepCompliance(const Eigen::VectorXd& f, Eigen::VectorXd& dx) {
  ++compliance_use_.calls;
  const bool ok = timed(compliance_use_.seconds, [&] {
    return compliance_.apply(*solver_, mask_, f, dx, [this] { return factorizeCompliance(); });
  });
  compliance_use_.iterations += compliance_.lastIterations();
  return ok;
}

}  // namespace surgical_sim::core
