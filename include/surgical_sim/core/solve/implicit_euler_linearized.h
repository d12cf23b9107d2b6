#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

#include "surgical_sim/core/solve/implicit_integrator_base.h"

namespace surgical_sim::core {

/// Linearized implicit Euler (Baraff & Witkin 1998): one Newton step of backward Euler,
///   (M + dt C + dt^2 K) dv = dt (f_int(x) + f_ext - C v - dt K v),  v += dv,  x += dt v,
/// with K = K(x_n) (TangentMode::ProjectedSpd) and C = alpha M + beta K. Dirichlet DOFs get the
/// velocity (target - x_d) / dt before the solve (dv_d = 0 by projection), so x_d = target.
/// A is assembled into a fixed pattern (SystemMatrix); the solver analyses it once per topology.
///
/// Energy safeguard: the step is the Newton step of the incremental potential
///   Phi(x) = |x - x_n - dt v_n|_M^2 / (2 dt^2) + W(x) - f_ext.x + (x - x_n)^T C (x - x_n) / (2
///   dt).
/// If the full step raises Phi (a single linearization overshooting on a stiff or strongly
/// nonlinear step), it is halved until Phi does not increase (at most max_line_search_halvings
/// times; then the smallest step is kept and NotConverged returned). This keeps the scheme from
/// creating energy; in ordinary steps the full step passes and costs one energy evaluation,
/// which is reused for the report. When a step starts where the last one ended (nothing moved the
/// state in between), its full step's energy is evaluated together with the force and stiffness
/// there (TissueModel::addInternalForceStiffnessAndEnergy), and the next step reuses them if it
/// too starts there: one element pass per step instead of two for models that combine them.
/// Changing the model in place (a cut) must be followed by reset() or modelChanged().
class ImplicitEulerLinearized final : public ImplicitIntegratorBase {
 public:
  /// @throws std::invalid_argument naming "solver" if linear_solver is null
  /// @param max_halvings energy-safeguard halvings per step [-], >= 0
  ImplicitEulerLinearized(std::unique_ptr<LinearSolver> linear_solver, int max_halvings);

  /// One step of dt [s] (> 0). Never throws. SolverFailed (state restored) if the problem is
  /// inconsistent or the factorization fails; NonFinite (state restored) on NaN/Inf.
  /// Report: newton_iterations = 1, residual = relative residual of the linear solve.
  /// name() "implicit_euler_linearized". applyStepCompliance: dx = dt^2 A^-1 f with the last
  /// step's projected system matrix A = M + dt C + dt^2 K(x_n) (its factorization is reused: one
  /// solve, no assembly), 0 on the last step's Dirichlet DOFs; when the energy safeguard
  /// shortened the last step, the response of the full step.
  StepReport step(const DynamicsProblem& problem, double dt, SimulationState& state) override;

 private:
  void resizeWorkspace(Eigen::Index size) override;
  /// Forgets W, f_int and K at the last step's end (and whether end_stiffness_'s pattern is K's).
  void forgetModelEvaluations() override;
  /// Phi at `x` (see the class comment), given W(x) [J].
  double incrementalPotential(const DynamicsProblem& problem, double dt, const Eigen::VectorXd& x,
                              double elastic_energy);
  /// W(x) [J], with end_force_ = f_int(x) and end_stiffness_ = K(x) (ProjectedSpd).
  double endForceStiffnessAndEnergy(const TissueModel& model, const Eigen::VectorXd& x);

  int max_halvings_;
  Eigen::VectorXd rhs_, dv_, product_, start_, direction_, offset_;
  /// W at the end of the last step and where it was evaluated (reused when the next step starts
  /// from the same positions, i.e. nothing moved the state in between).
  Eigen::VectorXd last_x_;
  double last_elastic_energy_ = 0.0;
  /// f_int and K at last_x_, valid when the last step evaluated them with its end energy.
  Eigen::VectorXd end_force_;
  Eigen::SparseMatrix<double> end_stiffness_;
  bool end_valid_ = false;
  /// end_stiffness_ has stiffness_'s pattern (checked once after a set-up or modelChanged()).
  bool end_pattern_checked_ = false;
};

}  // namespace surgical_sim::core
