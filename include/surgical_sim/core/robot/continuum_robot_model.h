#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/robot/block_tridiagonal_solver.h"
#include "surgical_sim/core/robot/chain_actuator.h"
#include "surgical_sim/core/robot/continuum_robot_description.h"
#include "surgical_sim/core/robot/equivalent_spring.h"
#include "surgical_sim/core/robot/rigid_node_pose.h"
#include "surgical_sim/core/robot/section_compliances.h"

namespace surgical_sim::core {

/// Numerical settings of ContinuumRobotModel::solveEquilibrium (documented choices).
struct ModelSolveSettings {
  int max_iterations = 100;  ///< Newton iterations [-], >= 1
  /// converged when |r| <= tol (|f_internal| + |f_external|) + a round-off floor [-], in (0, 1)
  double relative_tolerance = 1e-10;
};

/// Outcome of one equilibrium solve.
struct ModelSolveReport {
  StepStatus status = StepStatus::Ok;
  int iterations = 0;
  double residual = 0.0;  ///< final |r| [N, N m mixed]
};

/// Reduced continuum-robot model (Bosman ch. 5): rigid nodes 0..n (0 = base, clamped at rest)
/// joined by corotated equivalent springs from condensed section compliances; quasi-static
/// equilibrium sum of spring forces + gravity + actuator loads + tip force = 0 by Newton's method
/// (full step when it lowers the residual, else Armijo backtracking on the total potential; the
/// actuator load stiffness is reused from the last factorizeTangent, the spring part is exact),
/// block-tridiagonal tangent (6x6 blocks, moving nodes 1..n) solved in O(n); see
/// factorizeTangent(). All state in frame robot_base; allocation-free after
/// construction.
class ContinuumRobotModel {
 public:
  /// @param description validated robot description.
  /// @param compliances one 6x6 compliance per gap (computeSectionCompliances).
  /// @throws std::invalid_argument on an invalid description or a compliance count mismatch
  ///         ("continuum_robot.compliances").
  ContinuumRobotModel(const ContinuumRobotDescription& description,
                      const SectionCompliances& compliances);

  const ContinuumRobotDescription& description() const { return description_; }
  int numVertebrae() const { return description_.num_vertebrae; }
  int numActuators() const { return static_cast<int>(actuators_.size()); }
  /// 6 n: (dx, dtheta) of the moving rigid nodes 1..n.
  int numDofs() const { return 6 * description_.num_vertebrae; }
  const std::vector<std::unique_ptr<ChainActuator>>& actuators() const { return actuators_; }
  const std::vector<EquivalentSpring>& springs() const { return springs_; }

  /// Poses of rigid nodes 0..n.
  const std::vector<RigidNodePose>& nodes() const { return nodes_; }
  const std::vector<RigidNodePose>& restNodes() const { return rest_; }
  /// Overwrites the poses (size n+1; node 0 is kept at rest).
  void setNodes(const std::vector<RigidNodePose>& nodes);
  /// Back to the rest shape, zero tip force.
  void reset();
  /// Constant external force on the tip rigid node [N], frame robot_base.
  void setTipForce(const Eigen::Vector3d& f_B) { tip_force_ = f_B; }
  /// Tip position p_BT = position of rigid node n [m].
  Eigen::Vector3d tipPosition() const { return nodes_.back().p_BN; }

  /// Total potential [J]: springs + gravity - sum lambda_a m_a(q) - f_tip . p_tip.
  double potential(const std::vector<RigidNodePose>& nodes, const Eigen::VectorXd& actuation) const;
  /// Generalized force on all rigid nodes (size 6(n+1), node-major (force, torque)) [N, N m].
  void generalizedForce(const std::vector<RigidNodePose>& nodes, const Eigen::VectorXd& actuation,
                        Eigen::VectorXd& force) const;
  /// Quasi-static equilibrium under `actuation` (size numActuators(), [Pa] / [N]) from the current
  /// poses. Never throws; on SolverFailed / NonFinite the poses are restored.
  ModelSolveReport solveEquilibrium(const Eigen::VectorXd& actuation,
                                    const ModelSolveSettings& settings);

  /// Assembles and factorizes the block-tridiagonal tangent at the current poses under
  /// `actuation`: symmetrized exact spring stiffness + actuator load stiffness -sum lambda_a
  /// d^2m_a/dq^2 (unit Hessians of each actuator piece by forward differences of its gradient,
  /// recomputed here and cached); if that is not positive definite, the Gauss-Newton spring
  /// stiffness alone. Returns false if neither factorizes.
  bool factorizeTangent(const Eigen::VectorXd& actuation);
  /// Tangent after factorizeTangent() (assembled blocks and factor).
  const BlockTridiagonalSolver& tangent() const { return tangent_; }
  /// Row a of J_a at the current poses over the moving DOFs (size 6n): dm_a/dq.
  void actuatorJacobianRow(int a, Eigen::Ref<Eigen::VectorXd> row);

 private:
  bool assembleTangent(SpringTangent mode, const Eigen::VectorXd& actuation);
  /// Unit-actuation load Hessians of every actuator piece at the current poses into the cache.
  void computeLoadHessians();
  /// factorizeTangent with the cached load Hessians (computed first if invalid): the Newton
  /// tangent of solveEquilibrium, whose load term is thus evaluated at the poses of the last
  /// factorizeTangent / reset (a chord update; the residual stays exact).
  bool factorizeCachedTangent(const Eigen::VectorXd& actuation);

  ContinuumRobotDescription description_;
  std::vector<EquivalentSpring> springs_;
  std::vector<std::unique_ptr<ChainActuator>> actuators_;
  std::vector<double> mass_;  ///< lumped mass per rigid node [kg]
  std::vector<RigidNodePose> rest_, nodes_;
  std::vector<RigidNodePose> trial_, backup_;  ///< line-search and restore work lists
  Eigen::Vector3d tip_force_ = Eigen::Vector3d::Zero();
  /// d^2m/dq^2 per actuator piece at unit actuation, frame robot_base, shape 12x12 each;
  /// actuator a's pieces start at load_hessian_begin_[a].
  std::vector<Eigen::Matrix<double, 12, 12>> load_hessian_;
  std::vector<int> load_hessian_begin_;
  bool load_hessian_valid_ = false;
  double force_floor_ = 0.0;  ///< residual round-off floor [N]
  BlockTridiagonalSolver tangent_;
  Eigen::VectorXd full_;      ///< 6(n+1) work
  Eigen::VectorXd step_;      ///< 6n work
  Eigen::VectorXd residual_;  ///< 6n work
};

}  // namespace surgical_sim::core
