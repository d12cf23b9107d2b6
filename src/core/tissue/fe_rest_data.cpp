#include "surgical_sim/core/tissue/fe_rest_data.h"

#include <Eigen/LU>
#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "surgical_sim/core/tissue/element_basis.h"

namespace surgical_sim::core {
namespace {

[[noreturn]] void failDeterminant(int e, const char* where, double det) {
  std::ostringstream msg;
  msg << "mesh.elements: element " << e << " is inverted or degenerate at a " << where
      << " quadrature point (det dX/dxi = " << det << " m^3, must be > 0)";
  throw std::invalid_argument(msg.str());
}

/// What both evaluations share: sizing the data with zeroed accumulators, the shape values at the
/// mass points (the same for every element) and the mass accumulation of one element.
struct RestDataBuilder {
  RestDataBuilder(const TetMesh& mesh, FeRestData& data) : basis(mesh.type) {
    const QuadratureRule& mass_rule = basis.massRule();
    data.points_per_element = static_cast<int>(basis.stiffnessRule().weights.size());
    const auto points = static_cast<size_t>(mesh.numElements()) * data.points_per_element;
    data.rest_gradients.resize(points * basis.numNodes() * 3);
    data.weight_det_j.resize(points);
    data.body_weight = Eigen::VectorXd::Zero(mesh.numNodes());
    data.lumped_mass = Eigen::VectorXd::Zero(3 * mesh.numNodes());
    mass_shape_values.resize(basis.numNodes(), mass_rule.weights.size());
    for (Eigen::Index q = 0; q < mass_rule.weights.size(); ++q) {
      mass_shape_values.col(q) = basis.shapeValues(mass_rule.points.col(q));
    }
    rho_w.resize(mass_rule.weights.size());
    diagonal.resize(basis.numNodes());
  }

  /// Adds element e's consistent-mass diagonal, HRZ-scaled to sum to the element mass, and its
  /// body-force weights, from rho_w.
  void addElementMass(const Eigen::MatrixXi& elements, int e, FeRestData& data) {
    const Eigen::MatrixXd& N = mass_shape_values;
    diagonal.setZero();
    double element_mass = 0.0;
    for (Eigen::Index q = 0; q < N.cols(); ++q) {
      diagonal += rho_w(q) * N.col(q).cwiseAbs2();
      element_mass += rho_w(q);
      for (Eigen::Index a = 0; a < N.rows(); ++a) {
        data.body_weight(elements(a, e)) += rho_w(q) * N(a, q);
      }
    }
    diagonal *= element_mass / diagonal.sum();
    for (Eigen::Index a = 0; a < N.rows(); ++a) {
      data.lumped_mass.segment<3>(3 * elements(a, e)).array() += diagonal(a);
    }
  }

  ElementBasis basis;
  Eigen::MatrixXd mass_shape_values;  ///< N_a at mass point q, npe x q [-]
  Eigen::VectorXd rho_w;              ///< per mass point of the current element: rho w det J [kg]
  Eigen::VectorXd diagonal;           ///< scratch: the current element's mass diagonal [kg]
};

FeRestData genericRestData(const TetMesh& mesh, double density) {
  FeRestData data;
  RestDataBuilder builder(mesh, data);
  const ElementBasis& basis = builder.basis;
  const QuadratureRule& rule = basis.stiffnessRule();
  const QuadratureRule& mass_rule = basis.massRule();
  const int npe = basis.numNodes();
  Eigen::Matrix3Xd X_e(3, npe);
  Eigen::MatrixXd dN_dX(npe, 3);
  for (int e = 0; e < mesh.numElements(); ++e) {
    for (int a = 0; a < npe; ++a) X_e.col(a) = mesh.nodes.col(mesh.elements(a, e));
    for (int q = 0; q < data.points_per_element; ++q) {
      const double det = basis.restGradients(X_e, rule.points.col(q), dN_dX);
      if (!(det > 0.0)) failDeterminant(e, "stiffness", det);
      const size_t k = static_cast<size_t>(e) * data.points_per_element + q;
      std::copy(dN_dX.data(), dN_dX.data() + npe * 3, data.rest_gradients.begin() + k * npe * 3);
      data.weight_det_j[k] = rule.weights(q) * det;
    }
    for (int q = 0; q < mass_rule.weights.size(); ++q) {
      const double det = basis.restGradients(X_e, mass_rule.points.col(q), dN_dX);
      if (!(det > 0.0)) failDeterminant(e, "mass", det);
      builder.rho_w(q) = density * mass_rule.weights(q) * det;
    }
    builder.addElementMass(mesh.elements, e, data);
  }
  return data;
}

// Tet4: J = dX/dxi is the constant edge matrix, so every quadrature point shares det J and
// dN/dX = dN/dxi J^-1 with dN/dxi = [-1 -1 -1; I].
FeRestData tet4RestData(const TetMesh& mesh, double density) {
  FeRestData data;
  RestDataBuilder builder(mesh, data);
  const double weight = builder.basis.stiffnessRule().weights(0);
  const Eigen::VectorXd& mass_weights = builder.basis.massRule().weights;
  for (int e = 0; e < mesh.numElements(); ++e) {
    const Eigen::Vector3d X0 = mesh.nodes.col(mesh.elements(0, e));
    Eigen::Matrix3d J;
    for (int k = 0; k < 3; ++k) J.col(k) = mesh.nodes.col(mesh.elements(k + 1, e)) - X0;
    const double det = J.determinant();
    if (!(det > 0.0)) failDeterminant(e, "stiffness", det);
    const Eigen::Matrix3d J_inv = J.inverse();
    Eigen::Map<Eigen::Matrix<double, 4, 3>> G(data.rest_gradients.data() +
                                              static_cast<size_t>(e) * 12);
    G.row(0) = -(J_inv.row(0) + J_inv.row(1) + J_inv.row(2));
    G.bottomRows<3>() = J_inv;
    data.weight_det_j[static_cast<size_t>(e)] = weight * det;
    for (Eigen::Index q = 0; q < mass_weights.size(); ++q) {
      builder.rho_w(q) = density * mass_weights(q) * det;
    }
    builder.addElementMass(mesh.elements, e, data);
  }
  return data;
}

}  // namespace

FeRestData computeFeRestData(const TetMesh& mesh, double density, FeRestEvaluation evaluation) {
  if (mesh.type == ElementType::Tet4 && evaluation == FeRestEvaluation::Fastest) {
    return tet4RestData(mesh, density);
  }
  return genericRestData(mesh, density);
}

}  // namespace surgical_sim::core
