#pragma once

#include <Eigen/Core>
#include <vector>

#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// Rayleigh damping C = alpha M + beta K(x). Both zero means no damping matrix is built.
struct RayleighDamping {
  double mass_coefficient = 0.0;       ///< alpha [1/s], >= 0
  double stiffness_coefficient = 0.0;  ///< beta [s], >= 0 (Kelvin-Voigt-like viscosity)
  bool active() const { return mass_coefficient > 0.0 || stiffness_coefficient > 0.0; }
};

/// Dirichlet boundary condition: listed DOFs (index into the 3n vector) follow prescribed
/// positions. Imposed by projection (rows/columns of the system zeroed, unit diagonal).
struct DirichletBc {
  std::vector<int> dofs;      ///< constrained DOF indices, each in [0, 3n)
  Eigen::VectorXd positions;  ///< prescribed positions [m], same length as dofs
};

/// Everything an integrator needs besides the state. Non-owning reference to the model.
struct DynamicsProblem {
  const TissueModel* model = nullptr;
  Eigen::VectorXd external_force;  ///< constant-over-step external nodal force [N], size 3n
  RayleighDamping damping;
  DirichletBc dirichlet;
};

/// Dynamic state: positions [m] and velocities [m/s], size 3n each; time [s].
struct SimulationState {
  Eigen::VectorXd x;
  Eigen::VectorXd v;
  double time = 0.0;
};

}  // namespace surgical_sim::core
