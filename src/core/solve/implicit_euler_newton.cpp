#include "surgical_sim/core/solve/implicit_euler_newton.h"

#include <cmath>
#include <stdexcept>

#include "surgical_sim/core/solve/absolute_product_norm.h"
#include "surgical_sim/core/solve/armijo_line_search.h"
#include "surgical_sim/core/solve/dirichlet_projection.h"
#include "surgical_sim/core/solve/dynamics_problem_check.h"
#include "surgical_sim/core/solve/mechanical_energy.h"
#include "surgical_sim/core/solve/newton_constants.h"

namespace surgical_sim::core {
ImplicitEulerNewton::ImplicitEulerNewton(const IntegratorSettings& settings,
                                         std::unique_ptr<LinearSolver> linear_solver)
    : settings_(settings), solver_(std::move(linear_solver)) {
  validateIntegratorSettings(settings);
  if (!solver_) {
    throw std::invalid_argument("solver: implicit_euler_newton needs a linear solver (null)");
  }
}

std::string ImplicitEulerNewton::name() const { return "implicit_euler_newton"; }

void ImplicitEulerNewton::reset() {
  model_ = nullptr;
  compliance_.invalidate();
}

void ImplicitEulerNewton::setUp(const TissueModel& model) {
  const Eigen::SparseMatrix<double>& pattern = model.stiffnessPattern();
  const Eigen::Index size = pattern.rows();
  model_ = &model;
  stiffness_ = pattern;
  stiffness_.makeCompressed();
  damping_stiffness_ = stiffness_;
  system_.setPattern(stiffness_);
  solver_->analyzePattern(system_.matrix());
  mask_.assign(static_cast<size_t>(size), 0);
  for (Eigen::VectorXd* v : {&x0_, &v0_, &x_hat_, &force_, &residual_, &rhs_, &dx_, &trial_,
                             &offset_, &damping_product_, &work_, &compliance_x_}) {
    v->setZero(size);
  }
  compliance_.invalidate();
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

double ImplicitEulerNewton::computeResidual(const DynamicsProblem& problem, double dt,
                                            const Eigen::VectorXd& x, double* scale) {
  const Eigen::VectorXd& mass = problem.model->lumpedMass();
  force_ = problem.external_force;
  problem.model->addInternalForce(x, force_);
  const double dt2 = dt * dt;
  residual_ = mass.cwiseProduct(x - x_hat_);
  double terms = residual_.norm() + mass.cwiseProduct(x).norm() + dt2 * stiffness_round_off_ +
                 dt2 * (force_.norm() + 2.0 * problem.external_force.norm());
  residual_.noalias() -= dt2 * force_;
  if (problem.damping.active()) {
    applyFrozenDamping(problem, x);
    residual_.noalias() += dt * damping_product_;
    terms += dt * damping_product_.norm();
  }
  zeroDirichletEntries(problem.dirichlet.dofs, residual_);
  *scale = terms;
  return residual_.norm();
}

double ImplicitEulerNewton::merit(const DynamicsProblem& problem, double dt,
                                  const Eigen::VectorXd& x, double* scale) {
  const Eigen::VectorXd& mass = problem.model->lumpedMass();
  const double inertia = 0.5 * (mass.array() * (x - x_hat_).array().square()).sum();
  const double elastic = dt * dt * problem.model->energy(x);
  const double external = -dt * dt * problem.external_force.dot(x - x0_);
  double damping = 0.0;
  if (problem.damping.active()) {
    applyFrozenDamping(problem, x);
    damping = 0.5 * dt * offset_.dot(damping_product_);
  }
  *scale = std::abs(inertia) + std::abs(elastic) + std::abs(external) + std::abs(damping);
  return inertia + elastic + external + damping;
}

bool ImplicitEulerNewton::newtonDirection(const DynamicsProblem& problem, double dt,
                                          const Eigen::VectorXd& x, TangentMode mode,
                                          StepReport& report) {
  const double alpha = problem.damping.mass_coefficient;
  const double beta = problem.damping.stiffness_coefficient;
  problem.model->assembleStiffness(x, mode, stiffness_);
  stiffness_round_off_ = absoluteProductNorm(stiffness_, x, work_);
  system_.assemble(problem.model->lumpedMass(), 1.0 + dt * alpha, stiffness_, dt * dt);
  if (beta > 0.0) system_.addStiffness(damping_stiffness_, dt * beta);
  system_.projectDirichlet(mask_);
  if (!solver_->factorize(system_.matrix())) return false;
  rhs_ = -residual_;
  dx_.setZero();
  const LinearSolveReport solve = solver_->solve(rhs_, dx_);
  report.linear_iterations += solve.iterations;
  return solve.ok && rhs_.dot(dx_) > 0.0;  // a descent direction of Phi
}

StepReport ImplicitEulerNewton::step(const DynamicsProblem& problem, double dt,
                                     SimulationState& state) {
  StepReport report;
  compliance_.invalidate();
  if (findProblemError(problem, state) != nullptr || !std::isfinite(dt) || !(dt > 0.0)) {
    report.status = StepStatus::SolverFailed;
    return report;
  }
  const TissueModel& model = *problem.model;
  if (model_ != &model || !system_.matchesPattern(model.stiffnessPattern())) setUp(model);
  const DirichletBc& bc = problem.dirichlet;
  markDirichletDofs(bc.dofs, mask_);
  x0_ = state.x;
  v0_ = state.v;
  auto fail = [&](StepStatus status) {
    state.x = x0_;
    state.v = v0_;
    report.status = status;
    return report;
  };

  x_hat_ = x0_ + dt * v0_;
  state.x = x_hat_;
  for (size_t k = 0; k < bc.dofs.size(); ++k) {
    state.x[bc.dofs[k]] = bc.positions[static_cast<Eigen::Index>(k)];
  }
  if (problem.damping.stiffness_coefficient > 0.0) {
    model.assembleStiffness(x0_, TangentMode::ProjectedSpd, damping_stiffness_);
  }

  stiffness_round_off_ = 0.0;
  double reference = 0.0;
  double previous_norm = 0.0;
  bool use_exact = false;
  report.status = StepStatus::NotConverged;
  for (int iteration = 0;; ++iteration) {
    double terms = 0.0;
    const double norm = computeResidual(problem, dt, state.x, &terms);
    if (!std::isfinite(norm)) return fail(StepStatus::NonFinite);
    if (iteration == 0) reference = norm;
    report.residual = reference > 0.0 ? norm / reference : 0.0;
    if (norm <= settings_.relative_tolerance * reference ||
        norm <= kNewtonResidualRoundOff * terms) {
      report.status = StepStatus::Ok;
      break;
    }
    if (iteration == settings_.max_iterations) break;
    if (iteration > 0 && norm > kNewtonStallRatio * previous_norm) use_exact = true;
    previous_norm = norm;

    report.newton_iterations = iteration + 1;
    if (use_exact && !newtonDirection(problem, dt, state.x, TangentMode::Exact, report)) {
      use_exact = false;
    }
    if (!use_exact && !newtonDirection(problem, dt, state.x, TangentMode::ProjectedSpd, report)) {
      return fail(dx_.allFinite() ? StepStatus::SolverFailed : StepStatus::NonFinite);
    }

    const double slope = -rhs_.dot(dx_);  // grad . dx with grad = -rhs_
    double scale = 0.0;
    const double value0 = merit(problem, dt, state.x, &scale);
    const LineSearchResult search =
        armijoLineSearch(value0, slope, scale, settings_.max_line_search_halvings, [&](double s) {
          trial_ = state.x + s * dx_;
          double unused_scale = 0.0;
          return merit(problem, dt, trial_, &unused_scale);
        });
    if (!search.accepted) break;  // keep the last (finite) iterate: NotConverged
    state.x = trial_;
  }

  state.v = (state.x - x0_) / dt;
  const double energy = mechanicalEnergy(model, state.x, state.v, problem.external_force);
  if (!state.x.allFinite() || !state.v.allFinite() || !std::isfinite(energy)) {
    return fail(StepStatus::NonFinite);
  }
  state.time += dt;
  compliance_x_ = state.x;
  last_dt_ = dt;
  last_damping_ = problem.damping;
  compliance_.markStale(dt * dt);
  report.energy = energy;
  return report;
}

bool ImplicitEulerNewton::factorizeCompliance() {
  const double dt = last_dt_;
  for (const TangentMode mode : {TangentMode::Exact, TangentMode::ProjectedSpd}) {
    model_->assembleStiffness(compliance_x_, mode, stiffness_);
    system_.assemble(model_->lumpedMass(), 1.0 + dt * last_damping_.mass_coefficient, stiffness_,
                     dt * dt);
    if (last_damping_.stiffness_coefficient > 0.0) {
      system_.addStiffness(damping_stiffness_, dt * last_damping_.stiffness_coefficient);
    }
    system_.projectDirichlet(mask_);
    if (solver_->factorize(system_.matrix())) return true;
  }
  return false;
}

bool ImplicitEulerNewton::applyStepCompliance(const Eigen::VectorXd& f, Eigen::VectorXd& dx) {
  return compliance_.apply(*solver_, mask_, f, dx, [this] { return factorizeCompliance(); });
}

}  // namespace surgical_sim::core
