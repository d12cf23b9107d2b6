#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>

#include "surgical_sim/core/solve/implicit_integrator_base.h"
#include "surgical_sim/core/solve/integrator_settings.h"

namespace surgical_sim::core {

/// Newton's method with an Armijo line search on a merit function whose gradient is the residual,
/// shared by ImplicitEulerNewton (incremental potential) and QuasiStaticNewton (total potential).
/// A scheme supplies the residual, the merit and the system matrix's coefficients; this class
/// runs the iteration:
///   - direction: A(x) dx = -r with A assembled from the tangent K(x) (assembleSystem),
///     Dirichlet-projected. Tangent ProjectedSpd; after an iteration that reduced |r| by less than
///     kNewtonStallRatio the Exact tangent is tried, kept while A factorizes and gives a descent
///     direction. A linear solve stopped at its iteration cap (LinearSolveReport::capped) is used
///     as an inexact direction when it is one of descent;
///   - convergence: |r| <= max(relative_tolerance |r_0|, kNewtonResidualRoundOff s) with r_0 the
///     residual at the start of the solve and s the round-off scale of r (the norms of its
///     terms), i.e. relative residual |r| / max(|r_0|, kNewtonResidualRoundOff s /
///     relative_tolerance) <= relative_tolerance. StepReport::residual is that relative residual:
///     |r| / |r_0| unless |r_0| is itself near round-off, and <= relative_tolerance exactly when
///     the solve converged.
class NewtonIntegratorBase : public ImplicitIntegratorBase {
 protected:
  /// Uses max_iterations, relative_tolerance, max_line_search_halvings of settings.
  /// @throws std::invalid_argument naming the offending "integrator.*" setting
  ///         (validateIntegratorSettings), or "solver" if linear_solver is null
  NewtonIntegratorBase(const IntegratorSettings& settings,
                       std::unique_ptr<LinearSolver> linear_solver, std::string name);

  /// Newton iterations from x (Dirichlet DOFs already at their targets) until convergence.
  /// Ok or NotConverged (max_iterations reached or no line-search step accepted; x is the last
  /// finite iterate); SolverFailed if no direction was found (factorization or solve failed, or
  /// not a descent direction); NonFinite on a NaN/Inf residual or direction. Adds to
  /// report.newton_iterations and report.linear_iterations; sets report.residual (see the class
  /// comment).
  StepStatus solveNewton(const DynamicsProblem& problem, Eigen::VectorXd& x, StepReport& report);

  /// residual_ = r(x) (gradient of the merit, 0 on Dirichlet DOFs); returns |residual_| and sets
  /// *scale to its round-off scale. May use stiffness_round_off_.
  virtual double computeResidual(const DynamicsProblem& problem, const Eigen::VectorXd& x,
                                 double* scale) = 0;
  /// The merit at x (its gradient is the residual); *scale = sum of its terms' magnitudes.
  virtual double merit(const DynamicsProblem& problem, const Eigen::VectorXd& x, double* scale) = 0;
  /// system_ = the scheme's system matrix from the tangent in stiffness_ and model_'s mass
  /// (unprojected).
  virtual void assembleSystem() = 0;
  /// Sizes the Newton work vectors, then the scheme's own (resizeNewtonWorkspace).
  void resizeWorkspace(Eigen::Index size) final;
  virtual void resizeNewtonWorkspace(Eigen::Index size) = 0;
  /// Factorizes A at compliance_x_: Exact tangent, ProjectedSpd if that fails.
  bool factorizeCompliance() final;

  IntegratorSettings settings_;
  Eigen::VectorXd residual_, rhs_, dx_, trial_, work_;
  double stiffness_round_off_ = 0.0;  ///< || |K| |x| || of the last assembly [N]
  Eigen::VectorXd compliance_x_;      ///< end point of the last step [m], size 3n

 private:
  /// Solves A(x) dx_ = -residual_ with the given tangent mode. Returns false if the factorization
  /// or solve failed or dx_ is not a descent direction.
  bool newtonDirection(const DynamicsProblem& problem, const Eigen::VectorXd& x, TangentMode mode,
                       StepReport& report);
};

}  // namespace surgical_sim::core
