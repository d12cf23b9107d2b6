#pragma once

#include <vector>

#include <Eigen/Core>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// A tensioned cable embedded in a tet mesh, as a TissueModel term for the full FE plant: each
/// eyelet is a fixed barycentric combination e_k = sum_j w_kj x_j of the corners of the element
/// containing it at rest; energy T L(x) with L = sum_k |e_{k+1} - e_k| the routing length and T
/// the tension [N]. Force -T dL/dx, stiffness T sum_k W_k^T (I - u u^T) / l_k W_k (positive
/// semi-definite). Having no mass, its lumpedMass() is zero.
class TendonModel final : public TissueModel {
 public:
  /// @param mesh Tet4 mesh [m] containing every eyelet.
  /// @param eyelets eyelet positions at rest [m], mesh frame, in routing order, at least 2.
  /// @throws std::invalid_argument "tendon.eyelets[i]" if an eyelet lies in no element.
  TendonModel(const TetMesh& mesh, const std::vector<Eigen::Vector3d>& eyelets);

  /// Cable tension T [N] (any finite value; >= 0 for a physical cable).
  void setTension(double tension) { tension_ = tension; }

  std::string name() const override { return "tendon"; }
  const Eigen::VectorXd& restPositions() const override { return rest_; }
  const Eigen::VectorXd& lumpedMass() const override { return mass_; }
  Eigen::VectorXd bodyForce(const Eigen::Vector3d& a) const override;
  double energy(const Eigen::VectorXd& x) const override;
  void addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const override;
  const Eigen::SparseMatrix<double>& stiffnessPattern() const override { return pattern_; }
  void assembleStiffness(const Eigen::VectorXd& x, TangentMode mode,
                         Eigen::SparseMatrix<double>& K) const override;
  void applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                      Eigen::VectorXd& y) const override;

 private:
  Eigen::Vector3d eyelet(const Eigen::VectorXd& x, int k) const;

  Eigen::VectorXd rest_, mass_;
  std::vector<Eigen::Vector4i> corners_;
  std::vector<Eigen::Vector4d> weights_;
  Eigen::SparseMatrix<double> pattern_;
  double tension_ = 0.0;
};

}  // namespace surgical_sim::core
