#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "surgical_sim/core/tissue/surface_mapping.h"

namespace surgical_sim::core {

/// Grasp: when the jaws close, the surface vertices within grasp_radius of the tool tip are
/// attached to the tool through the model nodes that carry them (each vertex's row of the
/// SurfaceMapping: the vertex itself for a tet model, its MLS particles for an EFG model). The
/// nodes' positions p_TN in the tool frame T are recorded; while grasping they are Dirichlet
/// targets p_SN = X_ST p_TN, so they and the vertices they carry (a mapping reproduces rigid
/// motions) move with the tool; opening the jaws releases them.
/// No allocation after the first grasp except when more nodes are captured than ever before.
class GraspConstraint {
 public:
  /// @param grasp_radius capture radius around the tip [m], finite and > 0
  /// @throws std::invalid_argument naming "tool.grasp_radius"
  explicit GraspConstraint(double grasp_radius);

  /// Opens or closes the jaws at tool pose X_ST. On closing, captures the nodes (weight != 0) of
  /// the surface vertices (mapping.vertices()) within grasp_radius of the tip at model positions
  /// x [m] (size 3n, in S), each once, except nodes with a DOF in fixed_mask (size 3n, 1 =
  /// already constrained). Never throws.
  void update(bool closed, const Eigen::Isometry3d& X_ST, const SurfaceMapping& mapping,
              const Eigen::VectorXd& x, const std::vector<std::uint8_t>& fixed_mask);

  /// True while the jaws are closed on tissue (at least one attached node). Closed jaws that
  /// captured nothing hold nothing: the tool then collides like any other tool.
  bool active() const { return closed_ && !nodes_.empty(); }
  /// Number of constrained DOFs (3 per attached node; 0 when open).
  int numDofs() const { return closed_ ? 3 * static_cast<int>(nodes_.size()) : 0; }
  /// Appends the attached DOFs (node-major) to dofs (capacity kept).
  void appendDofs(std::vector<int>& dofs) const;
  /// Writes the targets X_ST p_TN [m] (in S) of the attached DOFs, in appendDofs() order, into
  /// positions (size numDofs()).
  void writeTargets(const Eigen::Isometry3d& X_ST, Eigen::Ref<Eigen::VectorXd> positions) const;
  /// Force of the tissue on the jaws [N], S: the sum of force (e.g. the internal elastic force,
  /// size 3n) over the attached nodes.
  Eigen::Vector3d toolForce(const Eigen::VectorXd& force) const;
  const std::vector<int>& nodes() const { return nodes_; }  ///< attached nodes

 private:
  double grasp_radius_;
  bool closed_ = false;
  std::vector<int> nodes_;
  std::vector<Eigen::Vector3d> p_TN_;  ///< attached node positions in the tool frame [m]
};

}  // namespace surgical_sim::core
