#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace surgical_sim::core {

/// Generalized coordinates per rigid node: 3 translational, 3 rotational.
constexpr int kRigidNodeDofs = 6;

/// Configuration of the rigid nodes N of a connective layer in the tissue frame T.
///
/// Angular convention (used by every rigid-node vector: velocities, increments, forces and
/// stiffness): node i's 6 generalized entries are (dx, dtheta) with dtheta a rotation vector in
/// T (spatial), applied as p_TN += dx [m], R_TN <- exp(dtheta) R_TN [rad], so a point attached
/// to the node moves by dp = dx + dtheta x (p - p_TN). The same convention as RigidNodePose.
/// Velocities are (v [m/s], omega [rad/s], omega in T); generalized forces are (f [N],
/// torque [N m] about the node's position, in T), so that their virtual work is f.dx +
/// torque.dtheta. A 6n vector is node-major: (dx_0, dtheta_0, dx_1, dtheta_1, ...).
struct RigidNodeConfiguration {
  std::vector<Eigen::Vector3d> p_TN;     ///< positions [m]
  std::vector<Eigen::Quaterniond> q_TN;  ///< unit quaternions, same length as p_TN

  int numNodes() const { return static_cast<int>(p_TN.size()); }
};

/// Dynamic state of a connective layer: configuration, 6n velocities (v, omega per node) and
/// time [s].
struct RigidNodeState {
  RigidNodeConfiguration configuration;
  Eigen::VectorXd velocity;
  double time = 0.0;
};

/// config <- config (+) scale dq: p += scale dx, q <- exp(scale dtheta) q (renormalized) for
/// every node. Allocation-free.
/// @param dq increments, size 6 numNodes()
/// @throws std::invalid_argument if dq has the wrong size
void applyRigidNodeIncrement(const Eigen::VectorXd& dq, double scale,
                             RigidNodeConfiguration& config);

/// Checks a configuration: equal lengths, finite positions, unit quaternions (|q| within 1e-6 of
/// 1). @throws std::invalid_argument naming `what`, the node and the bad value.
void checkRigidNodeConfiguration(const RigidNodeConfiguration& config, const char* what);

}  // namespace surgical_sim::core
