#pragma once

#include <Eigen/Core>
#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Rest-configuration data of a Tet4 / Tet10 finite-element mesh (what FeModel precomputes):
/// per element and stiffness quadrature point (ElementBasis::stiffnessRule()) the rest gradients
/// dN/dX and weight * det J; per node the lumped (HRZ) mass and the consistent body-force weight
/// (ElementBasis::massRule()).
struct FeRestData {
  int points_per_element = 0;          ///< stiffness quadrature points per element
  std::vector<double> rest_gradients;  ///< per (element, point): dN/dX, npe x 3 col-major [1/m]
  std::vector<double> weight_det_j;    ///< per (element, point): w detJ [m^3]
  Eigen::VectorXd lumped_mass;         ///< 3n [kg]
  Eigen::VectorXd body_weight;         ///< n, integral(rho N_a dV) [kg]
};

/// How computeFeRestData() evaluates the element gradients.
enum class FeRestEvaluation {
  /// Tet4 in closed form (det J = 6 V of the corner edge matrix J = [X1-X0, X2-X0, X3-X0],
  /// dN_a/dX = row a-1 of J^-1 for a = 1..3, dN_0/dX = minus their sum), Tet10 as Generic.
  /// The default.
  Fastest,
  /// ElementBasis quadrature with its dynamic-size matrices for every element type: the
  /// reference the Tet4 closed form is tested against.
  Generic,
};

/// Rest data of `mesh` with density rho.
/// @param mesh Tet4 or Tet10 mesh [m] with node indices in range (checkTissueMesh()).
/// @param density rho [kg/m^3].
/// @throws std::invalid_argument if det J <= 0 at a quadrature point (the message names
///         "mesh.elements" and the element index).
FeRestData computeFeRestData(const TetMesh& mesh, double density,
                             FeRestEvaluation evaluation = FeRestEvaluation::Fastest);

}  // namespace surgical_sim::core
