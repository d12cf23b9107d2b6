#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/group_assembled_model.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {

/// Mass-spring tissue on the edges of a Tet4 mesh (Chendeb 2007 sec. 2.3, baseline model).
///
/// One spring per unique mesh edge j with rest length L0_j [m] and stiffness (Van Gelder's formula
/// extended to tets, Chendeb eq. 2.7) k_j = E * sum(V_e, tets e sharing edge j) / L0_j^2 [N/m].
/// Spring energy 1/2 k (l - L0)^2; exact Hessian block k [(1 - L0/l) I + (L0/l) n n^T], n the unit
/// edge direction; ProjectedSpd clamps (1 - L0/l) at >= 0. Masses rho sum(V_e)/4 per node.
/// Note: the model has no Poisson effect (it ignores nu) and its apparent E is mesh dependent.
class MassSpringModel final : public GroupAssembledModel {
 public:
  /// @throws std::invalid_argument for Tet10 meshes, invalid material, degenerate / inverted
  ///         rest elements (names "mesh.elements" and the element).
  MassSpringModel(const TetMesh& mesh, const Material& material);

  std::string name() const override { return "mass_spring"; }
  Eigen::VectorXd bodyForce(const Eigen::Vector3d& a) const override;
  double energy(const Eigen::VectorXd& x) const override;
  void addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const override;
  /// y = K(x) v [N], y resized to 3n.
  void applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                      Eigen::VectorXd& y) const override;

  /// Spring end nodes, shape 2 x s (one unique edge per column, smaller index first).
  const Eigen::Matrix2Xi& springs() const { return springs_; }
  /// Spring stiffnesses k_j [N/m], size s.
  const Eigen::VectorXd& springStiffness() const { return stiffness_; }
  /// Spring rest lengths L0_j [m], size s.
  const Eigen::VectorXd& restLength() const { return rest_length_; }

 private:
  void addGroupStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                         double* values) const override;
  /// 3 x 3 block H of spring j at x (the 6 x 6 spring Hessian is [H -H; -H H]).
  Eigen::Matrix3d springBlock(const Eigen::VectorXd& x, int j, TangentMode mode) const;

  Eigen::Matrix2Xi springs_;
  Eigen::VectorXd stiffness_;
  Eigen::VectorXd rest_length_;
};

}  // namespace surgical_sim::core
