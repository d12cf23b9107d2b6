#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

#include "surgical_sim/core/solve/newton_integrator_base.h"

namespace surgical_sim::core {

/// Fully implicit (backward) Euler solved by Newton's method on the incremental potential
///   Phi(x) = 1/2 (x - x_hat)^T M (x - x_hat) + dt^2 (W(x) - f_ext . (x - x_n))
///            + dt/2 (x - x_n)^T C_n (x - x_n),       x_hat = x_n + dt v_n,
/// (Phi = dt^2 x the usual potential), C_n = alpha M + beta K(x_n) frozen at the start of the
/// step (ProjectedSpd). Newton iteration, tangent choice, line search on Phi and convergence test:
/// NewtonIntegratorBase, with A = M + dt C_n + dt^2 K(x), r = grad Phi [kg m] on free DOFs and r_0
/// at the initial guess x_hat. Dirichlet DOFs are set to their targets in the initial guess and
/// kept there (projection). v = (x - x_n) / dt. NotConverged (finite state kept) when
/// max_iterations is reached or the line search fails.
class ImplicitEulerNewton final : public NewtonIntegratorBase {
 public:
  /// @throws std::invalid_argument as NewtonIntegratorBase's constructor
  ImplicitEulerNewton(const IntegratorSettings& settings, std::unique_ptr<LinearSolver> solver);

  /// One step of dt [s] (> 0). Never throws. SolverFailed (state restored) if the problem is
  /// inconsistent or no Newton direction is found; NonFinite (state restored) on NaN/Inf.
  /// name() "implicit_euler_newton". applyStepCompliance: dx = dt^2 A^-1 f with
  /// A = (1 + dt alpha) M + dt^2 K(x_{n+1}) + dt beta K(x_n) at the last iterate x_{n+1} (Exact
  /// tangent, ProjectedSpd if that is not positive definite), projected; the first call after a
  /// step assembles and factorizes A once, later calls only solve; 0 on the last step's Dirichlet
  /// DOFs; available after Ok and NotConverged steps.
  StepReport step(const DynamicsProblem& problem, double dt, SimulationState& state) override;

 private:
  void resizeNewtonWorkspace(Eigen::Index size) override;
  /// damping_stiffness_ takes stiffness_'s pattern.
  void patternAdopted() override;
  /// residual_ = grad Phi(x) on free DOFs; returns |residual_|, sets *scale to the norm sum of
  /// its terms (for the round-off floor).
  double computeResidual(const DynamicsProblem& problem, const Eigen::VectorXd& x,
                         double* scale) override;
  /// Phi(x); sets *scale to the sum of the magnitudes of its terms.
  double merit(const DynamicsProblem& problem, const Eigen::VectorXd& x, double* scale) override;
  /// system_ = (1 + dt alpha) M + dt^2 K + dt beta K(x_n), K the tangent in stiffness_.
  void assembleSystem() override;
  /// damping_product_ = C_n (x - x_n), using offset_ = x - x_n.
  void applyFrozenDamping(const DynamicsProblem& problem, const Eigen::VectorXd& x);

  Eigen::SparseMatrix<double> damping_stiffness_;  ///< K(x_n) for beta > 0
  Eigen::VectorXd x_hat_, force_, offset_, damping_product_;
  double dt_ = 0.0;          ///< dt of the current / last step [s]
  RayleighDamping damping_;  ///< damping of the current / last step
};

}  // namespace surgical_sim::core
