#include "surgical_sim/core/solve/newton_integrator_base.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/solve/absolute_product_norm.h"
#include "surgical_sim/core/solve/armijo_line_search.h"
#include "surgical_sim/core/solve/newton_constants.h"

namespace surgical_sim::core {

NewtonIntegratorBase::NewtonIntegratorBase(const IntegratorSettings& settings,
                                           std::unique_ptr<LinearSolver> linear_solver,
                                           std::string name)
    : ImplicitIntegratorBase(std::move(linear_solver), std::move(name)), settings_(settings) {
  validateIntegratorSettings(settings);
}

void NewtonIntegratorBase::resizeWorkspace(Eigen::Index size) {
  for (Eigen::VectorXd* v : {&residual_, &rhs_, &dx_, &trial_, &work_, &compliance_x_}) {
    v->setZero(size);
  }
  resizeNewtonWorkspace(size);
}

bool NewtonIntegratorBase::newtonDirection(const DynamicsProblem& problem, const Eigen::VectorXd& x,
                                           TangentMode mode, StepReport& report) {
  StepPhaseTimes& phases = report.phases;
  timed(phases.forces, [&] { problem.model->assembleStiffness(x, mode, stiffness_); });
  stiffness_round_off_ = absoluteProductNorm(stiffness_, x, work_);
  timed(phases.assembly, [&] {
    assembleSystem();
    system_.projectDirichlet(mask_);
  });
  if (!timed(phases.factorization, [&] {
        solver_->setLinearizationState(*problem.model, x);
        return solver_->factorize(system_.matrix());
      }))
    return false;
  rhs_ = -residual_;
  dx_.setZero();
  const LinearSolveReport solve =
      timed(phases.linear_solve, [&] { return solver_->solve(rhs_, dx_); });
  report.linear_iterations += solve.iterations;
  // A capped iterative solve is an inexact Newton direction; the line search and the residual
  // test decide what it is worth.
  return (solve.ok || solve.capped) && rhs_.dot(dx_) > 0.0;  // a descent direction of the merit
}

StepStatus NewtonIntegratorBase::solveNewton(const DynamicsProblem& problem, Eigen::VectorXd& x,
                                             StepReport& report) {
  stiffness_round_off_ = 0.0;
  double reference = 0.0;
  double previous_norm = 0.0;
  bool use_exact = false;
  bool search_failed = false;
  for (int iteration = 0;; ++iteration) {
    double terms = 0.0;
    const double norm =
        timed(report.phases.forces, [&] { return computeResidual(problem, x, &terms); });
    if (!std::isfinite(norm)) return StepStatus::NonFinite;
    if (iteration == 0) reference = norm;
    // |r| over |r_0| raised to the round-off floor over the tolerance: converged iff <= tol.
    const double denominator =
        std::max(reference, kNewtonResidualRoundOff * terms / settings_.relative_tolerance);
    report.residual = denominator > 0.0 ? norm / denominator : 0.0;
    if (report.residual <= settings_.relative_tolerance) return StepStatus::Ok;
    // After a failed line search the test above has rechecked x with the stiffness round-off
    // of the last assembly (a body at rest sits at round-off, where no search makes progress).
    if (search_failed || iteration == settings_.max_iterations) return StepStatus::NotConverged;
    if (iteration > 0 && norm > kNewtonStallRatio * previous_norm) use_exact = true;
    previous_norm = norm;

    ++report.newton_iterations;
    if (use_exact && !newtonDirection(problem, x, TangentMode::Exact, report)) use_exact = false;
    if (!use_exact && !newtonDirection(problem, x, TangentMode::ProjectedSpd, report)) {
      return dx_.allFinite() ? StepStatus::SolverFailed : StepStatus::NonFinite;
    }

    const double slope = -rhs_.dot(dx_);  // grad . dx with grad = -rhs_
    double scale = 0.0;
    const double value0 = merit(problem, x, &scale);
    const LineSearchResult search =
        armijoLineSearch(value0, slope, scale, settings_.max_line_search_halvings, [&](double s) {
          trial_ = x + s * dx_;
          double unused_scale = 0.0;
          return merit(problem, trial_, &unused_scale);
        });
    if (!search.accepted) {
      search_failed = true;
      continue;
    }
    x = trial_;
  }
}

bool NewtonIntegratorBase::factorizeCompliance() {
  for (const TangentMode mode : {TangentMode::Exact, TangentMode::ProjectedSpd}) {
    model_->assembleStiffness(compliance_x_, mode, stiffness_);
    assembleSystem();
    system_.projectDirichlet(mask_);
    solver_->setLinearizationState(*model_, compliance_x_);
    if (solver_->factorize(system_.matrix())) return true;
  }
  return false;
}

}  // namespace surgical_sim::core
