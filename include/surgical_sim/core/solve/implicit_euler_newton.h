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

/// Fully implicit (backward) Euler solved by Newton's method on the incremental potential
///   Phi(x) = 1/2 (x - x_hat)^T M (x - x_hat) + dt^2 (W(x) - f_ext . (x - x_n))
///            + dt/2 (x - x_n)^T C_n (x - x_n),       x_hat = x_n + dt v_n,
/// (Phi = dt^2 x the usual potential), C_n = alpha M + beta K(x_n) frozen at the start of the
/// step (ProjectedSpd). Each iteration solves (M + dt C_n + dt^2 K(x)) dx = -grad Phi, followed
/// by an Armijo backtracking line search on Phi. Tangent K(x): ProjectedSpd; after an iteration
/// that reduced the residual by less than half, the Exact tangent is tried (kept while the system
/// factorizes and gives a descent direction). Dirichlet DOFs
/// are set to their targets in the initial guess and kept there (projection). v = (x - x_n) / dt.
///
/// Convergence: |r| <= relative_tolerance |r_0| (r = grad Phi [kg m], free DOFs, r_0 at the
/// initial guess x_hat) or |r| at round-off of its terms. NotConverged (finite
/// state kept) when max_iterations is reached or the line search fails.
class ImplicitEulerNewton final : public Integrator {
 public:
  /// Uses max_iterations, relative_tolerance, max_line_search_halvings of settings.
  /// @throws std::invalid_argument naming the offending "integrator.*" setting
  ///         (validateIntegratorSettings), or "solver" if linear_solver is null
  ImplicitEulerNewton(const IntegratorSettings& settings,
                      std::unique_ptr<LinearSolver> linear_solver);

  /// Returns "implicit_euler_newton".
  std::string name() const override;
  /// One step of dt [s] (> 0). Never throws. SolverFailed (state restored) if the problem is
  /// inconsistent or a linear solve fails; NonFinite (state restored) on NaN/Inf.
  StepReport step(const DynamicsProblem& problem, double dt, SimulationState& state) override;
  /// Forgets the pattern and buffers (next step re-analyses).
  void reset() override;
  /// dx = dt^2 A^-1 f with A = (1 + dt alpha) M + dt^2 K(x_{n+1}) + dt beta K(x_n) at the last
  /// iterate x_{n+1} (Exact tangent, ProjectedSpd if that is not positive definite), projected.
  /// The first call after a step assembles and factorizes A once; later calls only solve.
  /// 0 on the last step's Dirichlet DOFs. Available after Ok and NotConverged steps.
  bool applyStepCompliance(const Eigen::VectorXd& f, Eigen::VectorXd& dx) override;

 private:
  void setUp(const TissueModel& model);
  /// Solves (M + dt C_n + dt^2 K(x)) dx_ = -residual_ with the given tangent mode. Returns false
  /// if the factorization or solve failed or dx_ is not a descent direction.
  bool newtonDirection(const DynamicsProblem& problem, double dt, const Eigen::VectorXd& x,
                       TangentMode mode, StepReport& report);
  /// residual_ = grad Phi(x) on free DOFs; returns |residual_|, sets *scale to the norm sum of
  /// its terms (for the round-off floor).
  double computeResidual(const DynamicsProblem& problem, double dt, const Eigen::VectorXd& x,
                         double* scale);
  /// Phi(x); sets *scale to the sum of the magnitudes of its terms.
  double merit(const DynamicsProblem& problem, double dt, const Eigen::VectorXd& x, double* scale);
  /// damping_product_ = C_n (x - x_n), using offset_ = x - x_n.
  void applyFrozenDamping(const DynamicsProblem& problem, const Eigen::VectorXd& x);

  IntegratorSettings settings_;
  std::unique_ptr<LinearSolver> solver_;
  const TissueModel* model_ = nullptr;
  SystemMatrix system_;
  Eigen::SparseMatrix<double> stiffness_;          ///< K(x) of the current iterate
  Eigen::SparseMatrix<double> damping_stiffness_;  ///< K(x_n) for beta > 0
  std::vector<std::uint8_t> mask_;
  Eigen::VectorXd x0_, v0_, x_hat_, force_, residual_, rhs_, dx_, trial_, offset_, damping_product_,
      work_;
  double stiffness_round_off_ = 0.0;  ///< || |K| |x| || of the last assembly [N]

  /// Assembles and factorizes the compliance matrix at compliance_x_. Returns false on failure.
  bool factorizeCompliance();
  StepCompliance compliance_;     ///< dt^2 A^-1 at the end point of the last step
  Eigen::VectorXd compliance_x_;  ///< end point of the last step [m], size 3n
  double last_dt_ = 0.0;          ///< dt of the last usable step [s]
  RayleighDamping last_damping_;  ///< damping of the last usable step
};

}  // namespace surgical_sim::core
