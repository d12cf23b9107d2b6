#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "surgical_sim/core/connective/connective_coupling.h"
#include "surgical_sim/core/connective/coupled_solver.h"
#include "surgical_sim/core/connective/rigid_node_model.h"
#include "surgical_sim/core/contact/contact_point.h"
#include "surgical_sim/core/mesh/surface.h"
#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// A surface that follows a connective layer by skinning: vertex v moves as
///   x_v = sum_j w_vj (p_j + R_j o_vj),   o_vj = Rbar_j^T (X_v - pbar_j),
/// with Shepard weights (exponent 2) on its nearest rigid nodes (weight 1 on a rigid node it
/// coincides with), the same rule as ConnectiveCoupling's attachments.
struct LayerSurface {
  Eigen::Matrix3Xd rest;       ///< vertex rest positions [m]
  Eigen::Matrix3Xi triangles;  ///< outward, counter-clockwise seen from outside
  struct Skin {
    int node = 0;
    double weight = 0.0;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< o_vj [m]
  };
  std::vector<std::vector<Skin>> skins;  ///< per vertex
};

/// A running multi-body scene (RuntimeScene::bodies): FE organs coupled by rigid-node connective
/// layers (ConnectiveCoupling), stepped by CoupledSolver's linearized implicit Euler with the
/// scene's Rayleigh damping and gravity, and the scene's tools. step() never throws.
///
/// Tools act through springs in the coupled system, so they are implicit in the step:
/// - contact: at the start of each step, every organ surface node inside a tool's capsule (tip,
///   shaft along the tool's -z) gets a spring of the tool's coupling_stiffness (proxy tools:
///   proxy_stiffness) [N/m] towards its projection on the capsule surface (a penalty spring).
///   When the springs' summed force at the step's start exceeds the tool's max_force, every
///   spring of the tool is scaled down to it (status ContactLimited). The spring targets stay
///   fixed during a step: a node may enter the capsule within a step by about (pushing force) /
///   stiffness and is pushed out in the next one; a capsule moving more than its radius per step
///   can pass through a node.
/// - grasp: closing the jaws holds every organ node (but fixed ones) within grasp.radius of the
///   tip, each by a spring of the same stiffness to its position in the tool frame at closing.
///   If the grasp's force on the tool exceeds max_force after a step, the jaws slip: the step
///   is repeated from its start without the grasp (status ContactLimited).
/// The tool force is the springs' force on the tool at the end of the step (contact springs
/// only while compressed along their normal).
class MultiBodySimulation {
 public:
  /// @throws std::invalid_argument naming the scene key (a scene without bodies, a fixed region
  ///         holding no node, a layer sampling that fails, an attachment reaching no node, ...).
  explicit MultiBodySimulation(const RuntimeScene& scene);
  ~MultiBodySimulation();
  MultiBodySimulation(const MultiBodySimulation&) = delete;
  MultiBodySimulation& operator=(const MultiBodySimulation&) = delete;

  /// Advances by the scene's time step. Status (stats.report.status): the solver's failure
  /// (SolverFailed / NonFinite, the state kept), else ContactLimited (a tool's force capped or
  /// a grasp slipped), else Ok.
  SimulationStepStats step();
  /// Back to the rest state, time 0, jaws open, no tool poses: a replay from here is
  /// bit-identical to one from construction.
  void reset();

  /// Tool tip pose X_ST in the tissue (scene) frame; ignored for a tool without contact.
  /// @throws std::invalid_argument (state unchanged) for a tool index out of range, a non-finite
  ///         pose, a linear part that is not a rotation (within 1e-6) or a tip farther than
  ///         1000 m from the origin
  void setToolPose(int tool, const Eigen::Isometry3d& X_ST);
  /// Closes (true) or opens the tool's jaws; closing holds the organ nodes near the tip (a tool
  /// without jaws or without a pose holds nothing).
  void setGrasp(int tool, bool closed);
  /// Contact model of tool `tool` after the last step: f0_S the force of the tissue on the tool
  /// [N], K_S = df/dp (minus the sum of the active springs' stiffness, along the normal for
  /// contact springs) [N/m]; zero when nothing touches the tool.
  ContactLinearization toolContact(int tool) const;

  int numTools() const { return static_cast<int>(scene_.tools.size()); }
  const RuntimeScene& scene() const { return scene_; }
  double timeStep() const { return scene_.time_step; }
  double time() const { return state_.time; }
  const CoupledState& state() const { return state_; }
  const ConnectiveCoupling& coupling() const { return *coupling_; }

  int numBodies() const { return static_cast<int>(meshes_.size()); }
  /// Body `body`'s rest mesh in the scene frame (its pose applied).
  const TetMesh& bodyMesh(int body) const { return meshes_[body]; }
  const SurfaceMesh& bodySurface(int body) const { return surfaces_[body]; }
  /// Node positions [m] of body `body` (size 3 n), scene frame.
  const Eigen::VectorXd& bodyPositions(int body) const { return state_.organ_positions[body]; }
  int numLayers() const { return static_cast<int>(layers_.size()); }
  const RigidNodeModel& layer(int layer) const { return *layers_[layer]; }
  /// The boundary surface of layer `layer` (tet_mesh: its mesh's boundary; poisson_disk: its
  /// hexahedron, each face split into 4 x 4 quads) and its skinning.
  const LayerSurface& layerSurface(int layer) const { return layer_surfaces_[layer]; }
  /// Vertex positions of layerSurface(layer) at the current state [m], 3 x n.
  Eigen::Matrix3Xd layerSurfacePositions(int layer) const;
  /// Organ nodes per body touched by a tool in the last step (may repeat).
  const std::vector<std::vector<int>>& contactNodes() const { return contact_nodes_; }
  /// Structures this scene built, e.g. {"coupling", "solver", "contact", "grasp"}.
  std::vector<std::string> components() const;

 private:
  struct Tool;
  /// Contact springs of every tool at the current state into loads_ (appended), capped.
  void addContactSprings(bool& limited);
  /// Grasp springs of every closed tool into loads_ (appended).
  void addGraspSprings();
  /// Tool forces and linearizations from the springs of loads_ at the current state.
  void measureTools();

  RuntimeScene scene_;
  std::vector<TetMesh> meshes_;
  std::vector<SurfaceMesh> surfaces_;
  std::vector<std::unique_ptr<TissueModel>> organs_;
  std::vector<std::unique_ptr<RigidNodeModel>> layers_;
  std::vector<LayerSurface> layer_surfaces_;
  std::unique_ptr<ConnectiveCoupling> coupling_;
  std::unique_ptr<CoupledSolver> solver_;
  CoupledSolverSettings solver_settings_;
  CoupledState rest_, state_, start_;
  CoupledLoads loads_;
  std::vector<Tool> tools_;
  /// Per spring of loads_: its tool, and for a contact spring its outward normal.
  std::vector<int> spring_tool_;
  std::vector<std::optional<Eigen::Vector3d>> spring_normal_;
  std::vector<std::vector<int>> contact_nodes_;
};

}  // namespace surgical_sim::core
