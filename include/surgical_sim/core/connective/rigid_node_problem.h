#pragma once

#include <Eigen/Core>
#include <vector>

#include "surgical_sim/core/connective/rigid_node_model.h"

namespace surgical_sim::core {

/// Everything a rigid-node solver needs besides the configuration. Non-owning.
struct RigidNodeProblem {
  const RigidNodeModel* model = nullptr;
  /// Uniform acceleration of the sample masses, e.g. gravity [m/s^2]
  /// (RigidNodeModel::addBodyForce).
  Eigen::Vector3d body_acceleration = Eigen::Vector3d::Zero();
  /// Constant generalized nodal load (f [N], torque [N m] per node), size 6n, or empty for none.
  Eigen::VectorXd external_force;
  /// Generalized DOFs (6 i + k: k < 3 translation, k >= 3 rotation of node i) held at their
  /// values in the configuration a solve starts from; to prescribe a motion, set those values in
  /// the configuration first. Must remove the rigid modes for the quasi-static solve.
  std::vector<int> fixed_dofs;
  double mass_damping = 0.0;       ///< Rayleigh alpha [1/s], >= 0 (implicit Euler)
  double stiffness_damping = 0.0;  ///< Rayleigh beta [s], >= 0 (implicit Euler)
};

/// @throws std::invalid_argument naming the field (model missing, external_force size, a fixed
///         DOF out of [0, 6n), negative or non-finite damping or body_acceleration)
void checkRigidNodeProblem(const RigidNodeProblem& problem);

}  // namespace surgical_sim::core
