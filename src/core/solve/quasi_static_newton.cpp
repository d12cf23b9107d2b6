#include "surgical_sim/core/solve/quasi_static_newton.h"

#include <cmath>
#include <stdexcept>

#include "surgical_sim/core/solve/absolute_product_norm.h"
#include "surgical_sim/core/solve/armijo_line_search.h"
#include "surgical_sim/core/solve/dirichlet_projection.h"
#include "surgical_sim/core/solve/dynamics_problem_check.h"
#include "surgical_sim/core/solve/mechanical_energy.h"
#include "surgical_sim/core/solve/newton_constants.h"

namespace surgical_sim::core {
QuasiStaticNewton::QuasiStaticNewton(const IntegratorSettings& settings,
                                     std::unique_ptr<LinearSolver> linear_solver)
    : settings_(settings), solver_(std::move(linear_solver)) {
  validateIntegratorSettings(settings);
  if (!solver_) throw std::invalid_argument("solver: quasi_static needs a linear solver (null)");
}

std::string QuasiStaticNewton::name() const { return "quasi_static"; }

void QuasiStaticNewton::reset() {
  model_ = nullptr;
  compliance_.invalidate();
}

void QuasiStaticNewton::setUp(const TissueModel& model) {
  const Eigen::SparseMatrix<double>& pattern = model.stiffnessPattern();
  const Eigen::Index size = pattern.rows();
  model_ = &model;
  stiffness_ = pattern;
  stiffness_.makeCompressed();
  system_.setPattern(stiffness_);
  solver_->analyzePattern(system_.matrix());
  mask_.assign(static_cast<size_t>(size), 0);
  for (Eigen::VectorXd* v : {&x0_, &v0_, &previous_load_, &load_, &targets_, &internal_, &residual_,
                             &rhs_, &dx_, &trial_, &work_, &compliance_x_}) {
    v->setZero(size);
  }
  compliance_.invalidate();
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

double QuasiStaticNewton::merit(const TissueModel& model, const Eigen::VectorXd& x,
                                double* scale) const {
  const double elastic = model.energy(x);
  const double external = -load_.dot(x - x0_);
  *scale = std::abs(elastic) + std::abs(external);
  return elastic + external;
}

bool QuasiStaticNewton::newtonDirection(const TissueModel& model, const Eigen::VectorXd& x,
                                        TangentMode mode, StepReport& report) {
  model.assembleStiffness(x, mode, stiffness_);
  stiffness_round_off_ = absoluteProductNorm(stiffness_, x, work_);
  system_.assemble(model.lumpedMass(), 0.0, stiffness_, 1.0);
  system_.projectDirichlet(mask_);
  if (!solver_->factorize(system_.matrix())) return false;
  rhs_ = -residual_;
  dx_.setZero();
  const LinearSolveReport solve = solver_->solve(rhs_, dx_);
  report.linear_iterations += solve.iterations;
  return solve.ok && rhs_.dot(dx_) > 0.0;  // a descent direction of Pi
}

StepStatus QuasiStaticNewton::solveIncrement(const DynamicsProblem& problem, Eigen::VectorXd& x,
                                             StepReport& report) {
  const TissueModel& model = *problem.model;
  const std::vector<int>& dofs = problem.dirichlet.dofs;
  for (const int d : dofs) x[d] = targets_[d];
  stiffness_round_off_ = 0.0;
  double reference = 0.0;
  double previous_norm = 0.0;
  bool use_exact = false;
  for (int iteration = 0;; ++iteration) {
    double terms = 0.0;
    const double norm = computeResidual(problem, x, &terms);
    if (!std::isfinite(norm)) return StepStatus::NonFinite;
    if (iteration == 0) reference = norm;
    report.residual = reference > 0.0 ? norm / reference : 0.0;
    if (norm <= settings_.relative_tolerance * reference ||
        norm <= kNewtonResidualRoundOff * terms) {
      return StepStatus::Ok;
    }
    if (iteration == settings_.max_iterations) return StepStatus::NotConverged;
    if (iteration > 0 && norm > kNewtonStallRatio * previous_norm) use_exact = true;
    previous_norm = norm;

    ++report.newton_iterations;
    if (use_exact && !newtonDirection(model, x, TangentMode::Exact, report)) use_exact = false;
    if (!use_exact && !newtonDirection(model, x, TangentMode::ProjectedSpd, report)) {
      return dx_.allFinite() ? StepStatus::SolverFailed : StepStatus::NonFinite;
    }

    const double slope = -rhs_.dot(dx_);  // grad . dx with grad = -rhs_
    double scale = 0.0;
    const double value0 = merit(model, x, &scale);
    const LineSearchResult search =
        armijoLineSearch(value0, slope, scale, settings_.max_line_search_halvings, [&](double s) {
          trial_ = x + s * dx_;
          double unused_scale = 0.0;
          return merit(model, trial_, &unused_scale);
        });
    if (!search.accepted) return StepStatus::NotConverged;
    x = trial_;
  }
}

StepReport QuasiStaticNewton::step(const DynamicsProblem& problem, double dt,
                                   SimulationState& state) {
  StepReport report;
  compliance_.invalidate();
  if (findProblemError(problem, state) != nullptr || !std::isfinite(dt)) {
    report.status = StepStatus::SolverFailed;
    return report;
  }
  const TissueModel& model = *problem.model;
  if (model_ != &model || !system_.matchesPattern(model.stiffnessPattern())) setUp(model);
  const DirichletBc& bc = problem.dirichlet;
  markDirichletDofs(bc.dofs, mask_);
  x0_ = state.x;
  v0_ = state.v;

  StepStatus status = StepStatus::Ok;
  for (int level = 0; level <= settings_.max_load_step_levels; ++level) {
    const int increments = 1 << level;
    state.x = x0_;
    status = StepStatus::Ok;
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
    state.x = x0_;
    state.v = v0_;
    report.status = usable ? StepStatus::NonFinite : status;
    return report;
  }
  state.v.setZero();
  const double energy = mechanicalEnergy(model, state.x, state.v, problem.external_force);
  if (!std::isfinite(energy)) {
    state.x = x0_;
    state.v = v0_;
    report.status = StepStatus::NonFinite;
    return report;
  }
  if (status == StepStatus::Ok) previous_load_ = problem.external_force;
  state.time += dt;
  compliance_x_ = state.x;
  compliance_.markStale(1.0);
  report.status = status;
  report.energy = energy;
  return report;
}

bool QuasiStaticNewton::factorizeCompliance() {
  for (const TangentMode mode : {TangentMode::Exact, TangentMode::ProjectedSpd}) {
    model_->assembleStiffness(compliance_x_, mode, stiffness_);
    system_.assemble(model_->lumpedMass(), 0.0, stiffness_, 1.0);
    system_.projectDirichlet(mask_);
    if (solver_->factorize(system_.matrix())) return true;
  }
  return false;
}

bool QuasiStaticNewton::applyStepCompliance(const Eigen::VectorXd& f, Eigen::VectorXd& dx) {
  return compliance_.apply(*solver_, mask_, f, dx, [this] { return factorizeCompliance(); });
}

}  // namespace surgical_sim::core
