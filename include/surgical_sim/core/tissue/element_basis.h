#pragma once

#include <Eigen/Core>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// A quadrature rule on the reference tetrahedron {xi >= 0, eta >= 0, zeta >= 0, xi+eta+zeta <= 1}
/// (volume 1/6). Points are reference coordinates (xi, eta, zeta), weights sum to 1/6.
struct QuadratureRule {
  Eigen::Matrix3Xd points;  ///< reference coordinates [-], shape 3 x q
  Eigen::VectorXd weights;  ///< weights [-], size q, sum 1/6
};

/// Lagrange shape functions of a Tet4 or Tet10 element on the reference tetrahedron, plus the
/// quadrature rules used by the FE tissue models.
///
/// Reference coordinates xi = (xi, eta, zeta) map to barycentric coordinates
/// L0 = 1 - xi - eta - zeta, L1 = xi, L2 = eta, L3 = zeta. Tet4: N_a = L_a. Tet10 (Gmsh order):
/// corners N_a = L_a (2 L_a - 1), mid-edge nodes N = 4 L_i L_j for 4:(0,1) 5:(1,2) 6:(0,2) 7:(0,3)
/// 8:(2,3) 9:(1,3).
class ElementBasis {
 public:
  explicit ElementBasis(ElementType type);

  ElementType type() const { return type_; }
  /// Nodes per element: 4 (Tet4) or 10 (Tet10).
  int numNodes() const { return type_ == ElementType::Tet10 ? 10 : 4; }

  /// Shape function values N_a(xi) [-], size numNodes().
  Eigen::VectorXd shapeValues(const Eigen::Vector3d& xi) const;
  /// Reference gradients dN_a/dxi [-], shape numNodes() x 3.
  Eigen::MatrixXd shapeGradients(const Eigen::Vector3d& xi) const;

  /// Rule for internal force and stiffness: Tet4 1-point centroid rule (degree 1, exact for the
  /// constant strain of P1), Tet10 4-point degree-2 rule.
  const QuadratureRule& stiffnessRule() const { return stiffness_rule_; }
  /// Rule for consistent mass and body force: Tet4 4-point degree-2 rule (exact for N_a N_b),
  /// Tet10 14-point degree-5 rule with positive weights (exact for N_a N_b on affine elements).
  const QuadratureRule& massRule() const { return mass_rule_; }

  /// Rest-configuration gradients at reference point xi of an element with nodes X_e [m]
  /// (3 x numNodes()): writes dN/dX [1/m] (numNodes() x 3) and returns det(dX/dxi) [m^3]
  /// (positive for a valid, positively oriented element; dN/dX is left unchanged if det = 0).
  double restGradients(const Eigen::Matrix3Xd& X_e, const Eigen::Vector3d& xi,
                       Eigen::MatrixXd& dN_dX) const;

 private:
  ElementType type_;
  QuadratureRule stiffness_rule_;
  QuadratureRule mass_rule_;
};

}  // namespace surgical_sim::core
