#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "surgical_sim/core/solve/integrator.h"
#include "surgical_sim/core/solve/integrator_settings.h"
#include "surgical_sim/core/solve/linear_solver.h"
#include "surgical_sim/core/solve/step_compliance.h"
#include "surgical_sim/core/solve/system_matrix.h"

namespace surgical_sim::core {

/// Quasi-static equilibrium f_int(x) + f_ext = 0 with Dirichlet DOFs at their targets, by Newton's
/// method (projected Dirichlet rows/columns) with an Armijo line search on
/// Pi(x) = W(x) - f_ext . (x - x_start). Tangent: ProjectedSpd K(x); after an iteration that
/// reduced the residual by less than half, the Exact tangent is tried (kept while it factorizes
/// and gives a descent direction), restoring quadratic convergence under compression.
/// Sets v = 0; dt only advances state.time.
///
/// Load stepping: the load path goes from the previous step's load and the current Dirichlet
/// positions to the new ones. A full-load solve is tried first; if it fails, the state is
/// restored and the increment is split into 2, 4, ..., 2^max_load_step_levels equal parts; on
/// the finest level an unconverged increment does not stop the path (NotConverged at the end).
/// Convergence per solve: |r| <= relative_tolerance |r_0| (r = -(f_int + f_ext) on free DOFs [N],
/// r_0 at the start of that solve) or |r| at round-off of |f_int| + |f_ext|.
/// The Dirichlet set must remove the rigid modes, otherwise K is singular (SolverFailed).
class QuasiStaticNewton final : public Integrator {
 public:
  /// Uses max_iterations, relative_tolerance, max_line_search_halvings and
  /// max_load_step_levels of settings.
  /// @throws std::invalid_argument naming the offending "integrator.*" setting
  ///         (validateIntegratorSettings), or "solver" if linear_solver is null
  QuasiStaticNewton(const IntegratorSettings& settings,
                    std::unique_ptr<LinearSolver> linear_solver);

  /// Returns "quasi_static".
  std::string name() const override;
  /// Solves for equilibrium under the problem's load and Dirichlet targets. Never throws.
  /// Ok; NotConverged (last, finite iterate kept) if even the finest load stepping did not
  /// converge; SolverFailed / NonFinite with the state restored.
  StepReport step(const DynamicsProblem& problem, double dt, SimulationState& state) override;
  /// Forgets pattern, buffers and the previous load (taken as zero again).
  void reset() override;
  /// dx = K^-1 f with the tangent K at the equilibrium found by the last step (Exact tangent,
  /// ProjectedSpd if that is not positive definite), projected. The first call after a step
  /// assembles and factorizes K once; later calls only solve. 0 on the last step's Dirichlet
  /// DOFs. Available after Ok and NotConverged steps.
  bool applyStepCompliance(const Eigen::VectorXd& f, Eigen::VectorXd& dx) override;

 private:
  void setUp(const TissueModel& model);
  /// Newton solve of one load increment (load_, targets_) starting from state.x.
  StepStatus solveIncrement(const DynamicsProblem& problem, Eigen::VectorXd& x, StepReport& report);
  /// Solves K(x) dx_ = -residual_ with the given tangent (assembled, projected). Returns false if
  /// the factorization or solve failed or dx_ is not a descent direction.
  bool newtonDirection(const TissueModel& model, const Eigen::VectorXd& x, TangentMode mode,
                       StepReport& report);
  /// residual_ = -(f_int(x) + load_) on free DOFs; returns its norm; *scale = its round-off
  /// scale |f_int| + |load_| + || |K| |x| ||.
  double computeResidual(const DynamicsProblem& problem, const Eigen::VectorXd& x, double* scale);
  /// Pi(x) = W(x) - load_ . (x - x0_); *scale = sum of the terms' magnitudes.
  double merit(const TissueModel& model, const Eigen::VectorXd& x, double* scale) const;

  IntegratorSettings settings_;
  std::unique_ptr<LinearSolver> solver_;
  const TissueModel* model_ = nullptr;
  SystemMatrix system_;
  Eigen::SparseMatrix<double> stiffness_;
  std::vector<std::uint8_t> mask_;
  Eigen::VectorXd x0_, v0_, previous_load_, load_, targets_, internal_, residual_, rhs_, dx_,
      trial_, work_;
  double stiffness_round_off_ = 0.0;  ///< || |K| |x| || of the last assembly [N]

  /// Assembles and factorizes the compliance matrix at compliance_x_. Returns false on failure.
  bool factorizeCompliance();
  StepCompliance compliance_;     ///< K^-1 at the end point of the last step
  Eigen::VectorXd compliance_x_;  ///< end point of the last step [m], size 3n
};

}  // namespace surgical_sim::core
