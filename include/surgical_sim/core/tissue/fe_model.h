#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/group_assembled_model.h"
#include "surgical_sim/core/tissue/hyperelastic_law.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {

/// Displacement-based hyperelastic finite elements on Tet4 (1 quadrature point, constant strain)
/// or Tet10 (4-point degree-2 rule) meshes, with any HyperelasticLaw.
///
/// Precomputed in the constructor: rest gradients dN/dX and weight * det J per element and
/// quadrature point, the lumped (HRZ) mass, the consistent body-force weights, the stiffness
/// pattern and the element-to-nonzero scatter map. Energy, force and stiffness evaluation allocate
/// nothing and run their element loops on threads() threads in the order of schedule(), so their
/// results are bit-identical for any thread count. Element stiffness
/// K_e = sum_q w_q detJ_q G_q^T (dP/dF) G_q, G_q = d vec(F)/d x_e; a projected Tet4 tangent that
/// the law gives as a rotated isotropic linear tensor (HyperelasticLaw::
/// rotatedLinearStressAndTangent, corotational) is assembled blockwise as R K0 R^T without the
/// 9 x 9 matrix.
///
/// Masses: Tet4 rho V / 4 per node; Tet10 HRZ lumping (diagonal of the consistent mass scaled to
/// the element mass, all positive). bodyForce is the consistent integral of rho N_a a (Tet10
/// corner nodes get negative weights -rho V / 20 on affine elements, which is correct).
class FeModel final : public GroupAssembledModel {
 public:
  /// @param mesh Tet4 or Tet10 mesh [m], corner tets positively oriented.
  /// @param material validated material (E [Pa], nu [-], rho [kg/m^3]); only rho is used here,
  ///        the elastic constants live in `law`.
  /// @param law constitutive law (not null).
  /// @throws std::invalid_argument for a null law, an invalid material, or a degenerate / inverted
  ///         rest element (the message names "mesh.elements" and the element index).
  FeModel(const TetMesh& mesh, const Material& material, std::unique_ptr<HyperelasticLaw> law);

  std::string name() const override { return law_->name(); }
  Eigen::VectorXd bodyForce(const Eigen::Vector3d& a) const override;
  double energy(const Eigen::VectorXd& x) const override;
  void addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const override;
  /// One element pass: the energy shares each point's deformation gradient (and, corotational
  /// Tet4 with ProjectedSpd, its rotation) with the force and stiffness.
  double addInternalForceStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode,
                                            Eigen::VectorXd& f,
                                            Eigen::SparseMatrix<double>& K) const override;
  /// y = K(x) v [N], y resized to 3n.
  void applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                      Eigen::VectorXd& y) const override;
  /// Node i: rotation (signed polar) of sum_e,q w_q detJ_q F_q over the quadrature points of the
  /// elements containing i (identity for a node in no element).
  bool nodeRotations(const Eigen::VectorXd& x,
                     std::vector<Eigen::Matrix3d>& rotations) const override;

  /// The constitutive law.
  const HyperelasticLaw& law() const { return *law_; }
  /// Element type of the mesh.
  ElementType elementType() const { return type_; }

 private:
  template <int NPE, int NQ>
  double energyImpl(const Eigen::VectorXd& x) const;
  template <int NPE, int NQ>
  void forceImpl(const Eigen::VectorXd& x, Eigen::VectorXd& f) const;
  /// Element stiffness matrices passed to sink(e, Ke); with a non-null f, also f += the force.
  /// Returns the elastic energy [J] with with_energy (equal to energy(x)), else 0.
  template <int NPE, int NQ, typename Sink>
  double stiffnessImpl(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                       bool with_energy, Sink&& sink) const;
  /// One element pass for the stiffness and, with f, the force.
  void addGroupStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                         double* values) const override;

  ElementType type_;
  int nodes_per_element_;
  int points_per_element_;
  std::unique_ptr<HyperelasticLaw> law_;
  Eigen::MatrixXi elements_;            ///< nodes_per_element x m
  Eigen::VectorXd body_weight_;         ///< n, integral(rho N_a dV) [kg]
  std::vector<double> rest_gradients_;  ///< per (element, point): dN/dX, npe x 3 col-major [1/m]
  std::vector<double> weight_det_j_;    ///< per (element, point): w detJ [m^3]
};

}  // namespace surgical_sim::core
