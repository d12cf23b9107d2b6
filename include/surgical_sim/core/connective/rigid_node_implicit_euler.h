#pragma once

#include <Eigen/Core>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/connective/rigid_node_problem.h"
#include "surgical_sim/core/connective/rigid_node_tangent_system.h"

namespace surgical_sim::core {

/// Settings of RigidNodeImplicitEuler (numerical, not physical: the defaults are documented
/// choices).
struct RigidNodeImplicitEulerSettings {
  /// Factorize the step's system every this many steps [-], >= 1; the steps in between solve
  /// their own system by conjugate gradients preconditioned with the last factor (a triangular
  /// solve pair costs far less than a factorization, and the system changes little between
  /// steps). 1 factorizes every step and solves directly.
  int refresh_interval = 10;
  /// Such a step's solve stops at |b - A dv| <= relative_tolerance |b| [-], in (0, 1).
  double relative_tolerance = 1e-10;
  /// Such a step refactorizes and solves directly if the conjugate gradients have not converged
  /// within this many iterations [-], >= 1.
  int max_pcg_iterations = 20;
};

/// Throws std::invalid_argument naming "refresh_interval", "relative_tolerance" or
/// "max_pcg_iterations" with its range if a setting is out of range.
void validateRigidNodeImplicitEulerSettings(const RigidNodeImplicitEulerSettings& settings);

/// Linearized implicit Euler (one Newton step, Baraff-Witkin) for rigid nodes:
///   (M + h D + h^2 K) dv = h (f(q_n) - D v_n - h K v_n),   D = alpha M + beta K,
///   v_{n+1} = v_n + dv,   p <- p + h v,   R <- exp(h omega) R (unit quaternion, renormalized),
/// with M the rigid-node mass (RigidNodeModel::assembleNodeMass: the consistent mass
/// assembleMass is singular along drilling modes) and K the symmetrized tangent at q_n
/// (RigidNodeTangentSystem; the configuration dependence of M, i.e. gyroscopic terms, is not
/// linearized). Fixed DOFs get
/// zero velocity and keep their values. The factor of A is reused across steps as
/// RigidNodeImplicitEulerSettings describes; every step's own system is solved either way.
class RigidNodeImplicitEuler {
 public:
  /// @throws std::invalid_argument if settings are out of range
  explicit RigidNodeImplicitEuler(const RigidNodeImplicitEulerSettings& settings = {});

  /// Advances state by dt [s] (finite, > 0). Ok; SolverFailed / NonFinite with the state
  /// restored. report.residual: |b - A dv| / |b| of the solve (<= relative_tolerance for a step
  /// solved iteratively); report.linear_iterations: 1 for a direct solve, else the conjugate
  /// gradient iterations; report.energy: kinetic (with the
  /// step's mass matrix) + elastic + body-force potential after the step [J]; report.phases:
  /// RigidNodeTangentSystem::phases() and the solve.
  /// @throws std::invalid_argument for a malformed problem, a state of the wrong size or a bad dt
  StepReport step(const RigidNodeProblem& problem, double dt, RigidNodeState& state);

  /// Successful factorizations of the step's system since construction (for tests and
  /// benchmarks).
  int factorizations() const { return factorizations_; }

 private:
  RigidNodeImplicitEulerSettings settings_;
  int factorizations_ = 0;
  int steps_since_factorization_ = 0;
  RigidNodeTangentSystem system_;
  RigidNodeConfiguration start_;
  Eigen::VectorXd start_velocity_, rhs_, dv_, product_;
};

}  // namespace surgical_sim::core
