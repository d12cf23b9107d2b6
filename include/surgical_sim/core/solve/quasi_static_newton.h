#pragma once

#include <Eigen/Core>
#include <memory>

#include "surgical_sim/core/solve/newton_integrator_base.h"

namespace surgical_sim::core {

/// Quasi-static equilibrium f_int(x) + f_ext = 0 with Dirichlet DOFs at their targets, by Newton's
/// method (NewtonIntegratorBase: projected Dirichlet rows/columns, A = K(x), the Exact tangent
/// after a stalled iteration restoring quadratic convergence under compression) with an Armijo
/// line search on Pi(x) = W(x) - f_ext . (x - x_start). Sets v = 0; dt only advances state.time.
///
/// Load stepping: the load path goes from the previous step's load and the current Dirichlet
/// positions to the new ones. A full-load solve is tried first; if it fails, the state is
/// restored and the increment is split into 2, 4, ..., 2^max_load_step_levels equal parts; on
/// the finest level an unconverged increment does not stop the path (NotConverged at the end).
/// Convergence per solve: |r| <= relative_tolerance |r_0| (r = -(f_int + f_ext) on free DOFs [N],
/// r_0 at the start of that solve) or |r| at round-off of |f_int| + |f_ext|.
/// The Dirichlet set must remove the rigid modes, otherwise K is singular (SolverFailed).
class QuasiStaticNewton final : public NewtonIntegratorBase {
 public:
  /// Uses max_load_step_levels of settings besides NewtonIntegratorBase's.
  /// @throws std::invalid_argument as NewtonIntegratorBase's constructor
  QuasiStaticNewton(const IntegratorSettings& settings,
                    std::unique_ptr<LinearSolver> linear_solver);

  /// Solves for equilibrium under the problem's load and Dirichlet targets. Never throws.
  /// Ok; NotConverged (last, finite iterate kept) if even the finest load stepping did not
  /// converge; SolverFailed / NonFinite with the state restored. report.residual: the largest
  /// over the increments of the load path kept. name() "quasi_static"; reset() also forgets the
  /// previous load (taken as zero again). applyStepCompliance: dx = K^-1 f with the tangent K at
  /// the equilibrium found by the last step (Exact tangent, ProjectedSpd if that is not positive
  /// definite), projected; the first call after a step assembles and factorizes K once, later
  /// calls only solve; 0 on the last step's Dirichlet DOFs; available after Ok and NotConverged
  /// steps.
  StepReport step(const DynamicsProblem& problem, double dt, SimulationState& state) override;

 private:
  void resizeNewtonWorkspace(Eigen::Index size) override;
  /// Newton solve of one load increment (load_, targets_) starting from x.
  StepStatus solveIncrement(const DynamicsProblem& problem, Eigen::VectorXd& x, StepReport& report);
  /// residual_ = -(f_int(x) + load_) on free DOFs; returns its norm; *scale = its round-off
  /// scale |f_int| + |load_| + || |K| |x| ||.
  double computeResidual(const DynamicsProblem& problem, const Eigen::VectorXd& x,
                         double* scale) override;
  /// Pi(x) = W(x) - load_ . (x - x0_); *scale = sum of the terms' magnitudes.
  double merit(const DynamicsProblem& problem, const Eigen::VectorXd& x, double* scale) override;
  /// system_ = K, the tangent in stiffness_.
  void assembleSystem() override;

  Eigen::VectorXd previous_load_, load_, targets_, internal_;
};

}  // namespace surgical_sim::core
