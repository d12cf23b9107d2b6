#include "surgical_sim/core/connective/rigid_node_quasi_static.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/solve/absolute_product_norm.h"
#include "surgical_sim/core/solve/armijo_line_search.h"
#include "surgical_sim/core/solve/dirichlet_projection.h"
#include "surgical_sim/core/solve/newton_constants.h"

namespace surgical_sim::core {
namespace {

/// Bounds of the linear solve's relative tolerance (the forcing term) and its MINRES iteration
/// cap.
constexpr double kMinForcing = 1e-12;
constexpr double kMaxForcing = 1e-2;
constexpr int kMaxRefinementIterations = 100;

}  // namespace

RigidNodeQuasiStatic::RigidNodeQuasiStatic(const RigidNodeNewtonSettings& settings)
    : settings_(settings) {
  if (settings_.max_iterations < 1 || settings_.max_halvings < 0) {
    std::ostringstream msg;
    msg << "RigidNodeNewtonSettings: max_iterations = " << settings_.max_iterations
        << " must be >= 1 and max_halvings = " << settings_.max_halvings << " >= 0";
    throw std::invalid_argument(msg.str());
  }
  requireInHalfOpenRange("RigidNodeNewtonSettings.relative_tolerance", settings_.relative_tolerance,
                         1e-16, 1.0, "");
}

double RigidNodeQuasiStatic::merit(const RigidNodeProblem& problem, const RigidNodeConfiguration& q,
                                   const Eigen::VectorXd& travelled, double* scale) const {
  const double elastic = problem.model->energy(q);
  const double body = problem.model->bodyForcePotential(q, problem.body_acceleration);
  const double external =
      problem.external_force.size() == 0 ? 0.0 : -problem.external_force.dot(travelled);
  *scale = std::abs(elastic) + std::abs(body) + std::abs(external);
  return elastic + body + external;
}

double RigidNodeQuasiStatic::residualNorm(const RigidNodeProblem& problem,
                                          const RigidNodeConfiguration& q) {
  work_.setZero(problem.model->numDofs());
  problem.model->addInternalForce(q, work_);
  problem.model->addBodyForce(q, problem.body_acceleration, work_);
  if (problem.external_force.size() != 0) work_ += problem.external_force;
  zeroDirichletEntries(problem.fixed_dofs, work_);
  return work_.norm();
}

StepReport RigidNodeQuasiStatic::solve(const RigidNodeProblem& problem, RigidNodeConfiguration& q) {
  checkRigidNodeProblem(problem);
  const RigidNodeModel& model = *problem.model;
  if (q.numNodes() != model.numNodes() || q.q_TN.size() != q.p_TN.size()) {
    std::ostringstream msg;
    msg << "RigidNodeQuasiStatic::solve: configuration of " << q.numNodes()
        << " rigid nodes for a model of " << model.numNodes();
    throw std::invalid_argument(msg.str());
  }
  StepReport report;
  start_ = q;
  history_.clear();
  travelled_.setZero(model.numDofs());
  load_.setZero(model.numDofs());
  model.addBodyForce(q, problem.body_acceleration, load_);
  if (problem.external_force.size() != 0) load_ += problem.external_force;
  const double load_scale = load_.norm();
  magnitude_.resize(model.numDofs());
  work_.resize(model.numDofs());

  for (int iteration = 0;; ++iteration) {
    if (!system_.assemble(problem, q, 0.0, 1.0)) {
      q = start_;
      report.status = StepStatus::SolverFailed;
      return report;
    }
    residual_ = system_.totalForce();
    zeroDirichletEntries(problem.fixed_dofs, residual_);
    const double scale = system_.internalForce().norm() + load_scale;
    const double norm = residual_.norm();
    if (!std::isfinite(norm)) {
      q = start_;
      report.status = StepStatus::NonFinite;
      return report;
    }
    // The scale raised to the round-off floor of the forces over the tolerance: a residual at
    // round-off (stiff, nearly incompressible layers) counts as converged.
    for (int i = 0; i < q.numNodes(); ++i)
      magnitude_.segment<kRigidNodeDofs>(kRigidNodeDofs * i) << q.p_TN[i].cwiseAbs(), 1.0, 1.0, 1.0;
    const double floor =
        kNewtonResidualRoundOff * absoluteProductNorm(system_.stiffness(), magnitude_, work_);
    const double denominator = std::max(scale, floor / settings_.relative_tolerance);
    report.residual = denominator > 0.0 ? norm / denominator : 0.0;
    history_.push_back(report.residual);
    if (report.residual <= settings_.relative_tolerance) break;
    if (iteration == settings_.max_iterations) {
      report.status = StepStatus::NotConverged;
      break;
    }
    // Inexact Newton with forcing term ~ the relative residual: quadratic near the solution.
    const double forcing = std::clamp(report.residual, kMinForcing, kMaxForcing);
    const LinearSolveReport linear =
        system_.solveUnshifted(residual_, increment_, forcing, kMaxRefinementIterations);
    if (!linear.ok) {
      q = start_;
      report.status = StepStatus::SolverFailed;
      return report;
    }
    double merit_scale = 0.0;
    const double merit0 = merit(problem, q, travelled_, &merit_scale);
    base_ = q;
    auto trial = [&](double s) {
      trial_ = base_;
      applyRigidNodeIncrement(increment_, s, trial_);
      trial_travelled_ = travelled_ + s * increment_;
    };
    // Armijo on the energy along a descent direction; else (the Newton step heads for a saddle
    // along drilling modes that load made unstable, or the energy cannot decrease measurably)
    // backtracking on the residual norm, which the Newton step decreases.
    bool accepted = false;
    if (residual_.dot(increment_) > 0.0) {
      accepted =
          armijoLineSearch(merit0, -residual_.dot(increment_), merit_scale, settings_.max_halvings,
                           [&](double s) {
                             trial(s);
                             double unused = 0.0;
                             return merit(problem, trial_, trial_travelled_, &unused);
                           })
              .accepted;
    }
    for (int halving = 0; !accepted && halving <= settings_.max_halvings; ++halving) {
      const double s = std::ldexp(1.0, -halving);
      trial(s);
      accepted = residualNorm(problem, trial_) <= (1.0 - 1e-4 * s) * norm;
    }
    ++report.newton_iterations;
    report.linear_iterations += linear.iterations;
    if (!accepted) {
      report.status = StepStatus::NotConverged;
      break;
    }
    q = trial_;
    travelled_ = trial_travelled_;
  }
  double unused = 0.0;
  report.energy = merit(problem, q, travelled_, &unused);
  return report;
}

}  // namespace surgical_sim::core
