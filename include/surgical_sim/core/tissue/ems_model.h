#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/group_assembled_model.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {

/// Chendeb's Extended Mass-Spring ("masse-liaison etendue", Goulette & Chendeb 2006): St
/// Venant-Kirchhoff P1 elasticity written with the 6 squared edge lengths L of each Tet4.
///
/// Edges of a tet (corners 0..3): 1:(0,1) 2:(0,2) 3:(0,3) 4:(1,2) 5:(2,3) 6:(3,1); v_k = x_k - x_0.
/// With C = sum_i C_i L_i (C_i = B^T G_i B, B = [X1-X0 X2-X0 X3-X0]^{-1}), per tet
///   W = vol0 dL^T MW dL,  dL = L - L0,  MW = (lambda/8) VTr VTr^T + (mu/4) MTr  (6 x 6),
///   VTr_i = tr C_i, MTr_ij = tr(C_i C_j),
/// and the corrected nodal force (errata 5-9 of the digest): c_k = (2 vol0 MW DL_k)^T dL
/// (4-vector),
///   f_n = -(c_1[n] v_1 + c_2[n] v_2 + c_3[n] v_3).
/// Exact stiffness: the Hessian of the quartic W, 2 vol0 J^T MW J + sum_i w_i d2L_i/dx2 with
/// J = dL/dx (6 x 12) and w = 2 vol0 MW dL; ProjectedSpd eigen-clamps each 12 x 12 element block.
/// Masses rho V/4 per node per tet.
class EmsModel final : public GroupAssembledModel {
 public:
  /// @throws std::invalid_argument for Tet10 meshes, invalid material, degenerate / inverted
  ///         rest elements (names "mesh.elements" and the element).
  EmsModel(const TetMesh& mesh, const Material& material);

  std::string name() const override { return "ems"; }
  Eigen::VectorXd bodyForce(const Eigen::Vector3d& a) const override;
  double energy(const Eigen::VectorXd& x) const override;
  void addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const override;
  /// y = K(x) v [N], y resized to 3n.
  void applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                      Eigen::VectorXd& y) const override;

 private:
  void addGroupStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                         double* values) const override;
  using Matrix6d = Eigen::Matrix<double, 6, 6>;
  using Matrix64d = Eigen::Matrix<double, 6, 4>;
  using Matrix12d = Eigen::Matrix<double, 12, 12>;
  using Vector6d = Eigen::Matrix<double, 6, 1>;

  /// Per-tet precomputation.
  struct Tet {
    double volume;      ///< rest volume [m^3]
    Vector6d rest_sq;   ///< L0, squared rest edge lengths [m^2]
    Matrix6d vol_mw;    ///< vol0 MW [J/m^4]
    Matrix64d mwdl[3];  ///< 2 vol0 MW DL_k [J/m^4]
  };

  Vector6d squaredEdgeDelta(const Eigen::VectorXd& x, int e) const;
  Matrix12d elementStiffness(const Eigen::VectorXd& x, int e, TangentMode mode) const;

  Eigen::MatrixXi elements_;  ///< 4 x m
  std::vector<Tet> tets_;
};

}  // namespace surgical_sim::core
