#include "surgical_sim/core/robot/inverse_controller.h"

#include <cmath>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

const char* toString(InverseStatus status) {
  switch (status) {
    case InverseStatus::Converged:
      return "converged";
    case InverseStatus::Unreachable:
      return "unreachable";
    case InverseStatus::MaxIterations:
      return "max_iterations";
    case InverseStatus::InvalidTarget:
      return "invalid_target";
    case InverseStatus::Interrupted:
      return "interrupted";
  }
  return "unknown";
}

void validateInverseControllerSettings(const InverseControllerSettings& s) {
  requireInRange("inverse_controller.model.max_iterations", s.model.max_iterations, 1, 10000, "");
  requireInHalfOpenRange("inverse_controller.model.relative_tolerance", s.model.relative_tolerance,
                         1e-300, 1.0, "");
  if (!(s.model.relative_tolerance > 0.0))
    throw std::invalid_argument("inverse_controller.model.relative_tolerance must be in (0, 1)");
  requireInRange("inverse_controller.qp_max_iterations", s.qp_max_iterations, 1, 100000, "");
  requireInHalfOpenRange("inverse_controller.regularization", s.regularization, 0.0, 1.0, "");
  requirePositive("inverse_controller.max_target_distance", s.max_target_distance, "m");
  requireInHalfOpenRange("inverse_controller.stall_tolerance", s.stall_tolerance, 1e-300, 1.0, "");
}

InverseController::InverseController(ContinuumRobotModel& model,
                                     const InverseControllerSettings& settings)
    : model_(model), settings_(settings), qp_(std::max(1, model.numActuators())) {
  validateInverseControllerSettings(settings_);
  const int m = model_.numActuators(), n = model_.numDofs();
  lo_.resize(m);
  hi_.resize(m);
  for (int a = 0; a < m; ++a) {
    lo_[a] = model_.actuators()[a]->lowerBound();
    hi_[a] = model_.actuators()[a]->upperBound();
  }
  lambda_ = Eigen::VectorXd::Zero(m);
  lambda_new_ = lambda_;
  lambda_prev_ = lambda_;
  c_.resize(m);
  delta_.resize(3);
  Ja_.resize(m, n);
  X_.resize(n, m);
  Wea_.resize(3, m);
  Waa_.resize(m, m);
  H_.resize(m, m);
  reset();
}

void InverseController::reset() {
  lambda_.setZero();
  lambda_ = lambda_.cwiseMax(lo_).cwiseMin(hi_);
  model_.reset();
  model_.solveEquilibrium(lambda_, settings_.model);
}

bool InverseController::iterate(const Eigen::Vector3d& p_target, int* qp_iterations) {
  const int m = model_.numActuators(), n = model_.numDofs();
  if (!model_.factorizeTangent(lambda_)) return false;
  for (int a = 0; a < m; ++a) {
    model_.actuatorJacobianRow(a, X_.col(a));
    Ja_.row(a) = X_.col(a).transpose();
    model_.tangent().solve(X_.col(a));
  }
  Wea_ = X_.middleRows<3>(n - 6);
  Waa_.noalias() = Ja_ * X_;
  Waa_ = 0.5 * (Waa_ + Waa_.transpose()).eval();
  delta_ = model_.tipPosition() - p_target;
  delta_.noalias() -= Wea_ * lambda_;
  H_.noalias() = Wea_.transpose() * Wea_;
  const double tr_aa = Waa_.trace();
  const double eps = tr_aa > 0.0 ? settings_.regularization * H_.trace() / tr_aa : 0.0;
  H_ += eps * Waa_;
  // Antagonistic actuator combinations (e.g. opposite cables pulled equally on an axisymmetric
  // robot) leave J_a rank deficient, so W_aa is only semi-definite: a tiny Tikhonov term picks
  // the smallest actuation among the equivalent ones.
  H_.diagonal().array() += 1e-9 * H_.trace() / H_.rows();
  c_.noalias() = Wea_.transpose() * delta_;
  lambda_new_ = lambda_;
  const BoxQpReport qp = qp_.solve(H_, c_, lo_, hi_, lambda_new_, settings_.qp_max_iterations);
  *qp_iterations += qp.iterations;
  if (qp.status == BoxQpStatus::NotConvex) return false;
  // Equilibrium under the new actuation; halve the actuation change if the model fails.
  for (int tries = 0; tries < 6; ++tries) {
    const ModelSolveReport rep = model_.solveEquilibrium(lambda_new_, settings_.model);
    if (rep.status == StepStatus::Ok || rep.status == StepStatus::NotConverged) {
      lambda_.swap(lambda_new_);
      return true;  // NotConverged: finite, usable state just above the tolerance
    }
    lambda_new_ = 0.5 * (lambda_ + lambda_new_);
  }
  return false;
}

void InverseController::solveTarget(const Eigen::Vector3d& p_target, double tolerance,
                                    int max_iterations, InverseResult& result) {
  result.iterations = 0;
  result.qp_iterations = 0;
  result.actuation = lambda_;
  result.effector_error = (model_.tipPosition() - p_target).norm();
  if (!p_target.allFinite() || p_target.norm() > settings_.max_target_distance ||
      !(tolerance > 0.0) || max_iterations < 1) {
    result.status = InverseStatus::InvalidTarget;
    result.message = !p_target.allFinite()
                         ? "target is not finite"
                         : (p_target.norm() > settings_.max_target_distance
                                ? "target is farther than max_target_distance from robot_base"
                                : "tolerance must be > 0 and max_iterations >= 1");
    return;
  }
  const double range = (hi_ - lo_).cwiseAbs().maxCoeff();
  double error = result.effector_error;
  result.status = InverseStatus::MaxIterations;
  result.message = "iteration limit reached";
  if (error <= tolerance) {
    result.status = InverseStatus::Converged;
    result.message = "target reached";
    return;
  }
  for (int it = 0; it < max_iterations; ++it) {
    if (cancelled_ && cancelled_()) {
      result.status = InverseStatus::Interrupted;
      result.message = "interrupted: the last iterate is returned";
      break;
    }
    lambda_prev_ = lambda_;
    const bool ok = iterate(p_target, &result.qp_iterations);
    ++result.iterations;
    const double change = (lambda_ - lambda_prev_).cwiseAbs().maxCoeff() / range;
    const double new_error = (model_.tipPosition() - p_target).norm();
    const double improvement = error - new_error;
    error = new_error;
    if (!ok) {
      result.status = InverseStatus::MaxIterations;
      result.message = "model equilibrium did not converge";
      break;
    }
    if (error <= tolerance) {
      result.status = InverseStatus::Converged;
      result.message = "target reached";
      break;
    }
    if (change <= settings_.stall_tolerance && improvement <= tolerance) {
      result.status = InverseStatus::Unreachable;
      result.message = "target unreachable: closest feasible actuation returned";
      break;
    }
  }
  result.actuation = lambda_;
  result.effector_error = error;
}

InverseResult InverseController::solveTarget(const Eigen::Vector3d& p_target, double tolerance,
                                             int max_iterations) {
  InverseResult result;
  result.actuation = lambda_;
  solveTarget(p_target, tolerance, max_iterations, result);
  return result;
}

InverseResult InverseController::step(const Eigen::Vector3d& p_target) {
  return solveTarget(p_target, 1e-12, 1);
}

}  // namespace surgical_sim::core
