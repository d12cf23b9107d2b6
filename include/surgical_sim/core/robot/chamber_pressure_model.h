#pragma once

#include <vector>

#include <Eigen/Core>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/robot/embedded_point.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// Gauge pressure in a closed cavity embedded in a tet mesh, as a TissueModel term of the full FE
/// plant (follower load). The cavity is a closed triangulated surface whose vertices are embedded
/// points of the mesh (barycentric in their rest element), the same surface the reduced model's
/// PressureChamberActuator skins to its rigid nodes. Energy -p V(x) with V = sum_t p0.(p1 x p2)/6
/// the enclosed volume [m^3]; nodal force f = p dV/dx: each triangle pushes its three vertices
/// with p A n / 3 (area-weighted outward normal), spread to the element corners by the weights.
/// Stiffness K = -p d2V/dx2 (symmetric, indefinite): assembled in TangentMode::Exact; in
/// TangentMode::ProjectedSpd the term contributes nothing (a load stiffness has no PSD part;
/// the residual stays exact, so Newton converges to the same equilibrium). No mass.
class ChamberPressureModel final : public TissueModel {
 public:
  /// @param mesh Tet4 mesh [m] containing every cavity vertex.
  /// @param vertices cavity vertices at rest [m], mesh frame.
  /// @param triangles vertex index triples oriented out of the cavity, closed surface.
  /// @throws std::invalid_argument "chamber_pressure.vertices[i]" if a vertex lies in no
  ///         element, "chamber_pressure.triangles[t]" if an index is out of range.
  ChamberPressureModel(const TetMesh& mesh, const std::vector<Eigen::Vector3d>& vertices,
                       const std::vector<Eigen::Vector3i>& triangles);

  /// Gauge pressure p [Pa] (any finite value).
  void setPressure(double pressure) { pressure_ = pressure; }
  /// Enclosed volume V(x) [m^3].
  double volume(const Eigen::VectorXd& x) const;

  std::string name() const override { return "chamber_pressure"; }
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
  /// Calls visit(i, j, H_ij) for the nonzero 3x3 blocks of d2V/dp_i dp_j of triangle t.
  template <class Visit>
  void forEachVolumeHessianBlock(const Eigen::VectorXd& x, int t, Visit&& visit) const;

  Eigen::VectorXd rest_, mass_;
  std::vector<EmbeddedPoint> points_;
  std::vector<Eigen::Vector3i> triangles_;
  Eigen::SparseMatrix<double> pattern_;
  double pressure_ = 0.0;
};

}  // namespace surgical_sim::core
