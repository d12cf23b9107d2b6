#pragma once

#include <Eigen/Core>
#include <vector>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/connective/rigid_node_problem.h"
#include "surgical_sim/core/connective/rigid_node_tangent_system.h"

namespace surgical_sim::core {

/// Settings of RigidNodeQuasiStatic.
struct RigidNodeNewtonSettings {
  int max_iterations = 50;           ///< Newton iterations, >= 1
  double relative_tolerance = 1e-9;  ///< see RigidNodeQuasiStatic::solve, in (0, 1)
  int max_halvings = 30;             ///< line-search halvings, >= 0
};

/// Quasi-static equilibrium f_int(q) + f_body(q) + f_ext = 0 of a rigid-node model by inexact
/// Newton: dq ~= A^-1 r with A the projected symmetrized tangent (RigidNodeTangentSystem; exact
/// at equilibrium, where the non-symmetric part, proportional to the nodal torques, vanishes),
/// solved by RigidNodeTangentSystem::solveUnshifted to a relative tolerance of the current
/// relative residual (in [1e-12, 1e-2]), r the residual force on free DOFs, q <- q (+) s dq
/// (applyRigidNodeIncrement). s: Armijo line search on Pi(q) = W(q) + V_body(q) - f_ext .
/// (sum of accepted increments) (external torques act as dead loads in the rotation increments)
/// when dq descends Pi, else (or if that search fails) halving until |r| decreases: under load,
/// the drilling modes of layouts that reproduce linear fields can have slightly negative
/// stiffness, and the equilibrium is then a saddle along them (they move no sample). Fixed
/// DOFs keep the values they have in q.
class RigidNodeQuasiStatic {
 public:
  /// @throws std::invalid_argument naming a setting out of range
  explicit RigidNodeQuasiStatic(const RigidNodeNewtonSettings& settings = {});

  /// Solves in place from q. Ok when converged: |r| <= tol (|f_int| + |f_load|), or |r| at the
  /// round-off floor kNewtonResidualRoundOff || |K| |z| || (z: the rigid nodes' |positions| [m]
  /// and 1 rad per rotation); NotConverged (last accepted iterate kept) at the iteration cap or
  /// when the line search finds no decrease; SolverFailed / NonFinite with q restored.
  /// report.residual: |r| / max(|f_int| + |f_load|, floor / tol) at the end.
  /// @throws std::invalid_argument for a malformed problem (checkRigidNodeProblem) or a q of
  ///         the wrong size
  StepReport solve(const RigidNodeProblem& problem, RigidNodeConfiguration& q);

  /// The tangent system of the last solve (its stiffness at the last assembled iterate).
  const RigidNodeTangentSystem& system() const { return system_; }
  /// Relative residual (as report.residual) at every iterate of the last solve, the start first.
  const std::vector<double>& residualHistory() const { return history_; }

 private:
  double merit(const RigidNodeProblem& problem, const RigidNodeConfiguration& q,
               const Eigen::VectorXd& travelled, double* scale) const;
  /// |total force on free DOFs| at q [N, N m mixed] (uses work_).
  double residualNorm(const RigidNodeProblem& problem, const RigidNodeConfiguration& q);

  RigidNodeNewtonSettings settings_;
  RigidNodeTangentSystem system_;
  RigidNodeConfiguration start_, base_, trial_;
  std::vector<double> history_;
  Eigen::VectorXd residual_, increment_, travelled_, trial_travelled_, load_, magnitude_, work_;
};

}  // namespace surgical_sim::core
