#pragma once

#include <Eigen/Core>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/connective/rigid_node_problem.h"
#include "surgical_sim/core/connective/rigid_node_tangent_system.h"

namespace surgical_sim::core {

/// Linearized implicit Euler (one Newton step, Baraff-Witkin) for rigid nodes:
///   (M + h D + h^2 K) dv = h (f(q_n) - D v_n - h K v_n),   D = alpha M + beta K,
///   v_{n+1} = v_n + dv,   p <- p + h v,   R <- exp(h omega) R (unit quaternion, renormalized),
/// with M the rigid-node mass (RigidNodeModel::assembleNodeMass: the consistent mass
/// assembleMass is singular along drilling modes) and K the symmetrized tangent at q_n
/// (RigidNodeTangentSystem; the configuration dependence of M, i.e. gyroscopic terms, is not
/// linearized). Fixed DOFs get
/// zero velocity and keep their values.
class RigidNodeImplicitEuler {
 public:
  /// Advances state by dt [s] (finite, > 0). Ok; SolverFailed / NonFinite with the state
  /// restored. report.residual: |b - A dv| / |b| of the solve; report.energy: kinetic (with the
  /// step's mass matrix) + elastic + body-force potential after the step [J]; report.phases:
  /// RigidNodeTangentSystem::phases() and the solve.
  /// @throws std::invalid_argument for a malformed problem, a state of the wrong size or a bad dt
  StepReport step(const RigidNodeProblem& problem, double dt, RigidNodeState& state);

 private:
  RigidNodeTangentSystem system_;
  RigidNodeConfiguration start_;
  Eigen::VectorXd start_velocity_, rhs_, dv_, product_;
};

}  // namespace surgical_sim::core
