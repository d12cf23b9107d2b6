#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/contact/contact_phase.h"
#include "surgical_sim/core/contact/contact_point.h"
#include "surgical_sim/core/cutting/blade_sweep.h"
#include "surgical_sim/core/cutting/tet_cutter.h"
#include "surgical_sim/core/mesh/surface.h"
#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/solve/dynamics_problem.h"
#include "surgical_sim/core/solve/integrator.h"
#include "surgical_sim/core/tissue/surface_mapping.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// Wall-clock phase times of one step [s] and the integrator's report. A phase the scene does
/// not use is never built and reads exactly 0.
struct SimulationStepStats {
  StepReport report;
  double step_seconds = 0.0;
  double collision_seconds = 0.0;
  double integrate_seconds = 0.0;
  double contact_seconds = 0.0;
  ContactTimings contact_timings;  ///< split of the contact phase (zero without tools) [ms]
  /// Blade detection and topology update (cutter, masses, model, surface, contact) [s]; 0 for a
  /// scene that never received a cut.
  double cut_seconds = 0.0;
  bool topology_changed = false;  ///< a cut changed the mesh during this step
  int contacts = 0;
};

/// One running tissue scene: its mesh, model, integrator and solver, boundary conditions and
/// loads, and its tools. Builds only what the scene needs: no contact structures without tools,
/// no damping work without damping, no cut structures before the first cut. step() never throws.
class TissueSimulation {
 public:
  /// Every model kind runs and can be cut (tet4 meshes with the tet cutter, efg with the meshless
  /// volume and surface cutters). A body given by a closed surface (mesh.generator liver) runs the
  /// efg model only: its cells are sampled inside the surface and all of the surface's vertices are
  /// mapped.
  /// @throws std::invalid_argument / std::runtime_error naming the scene key on bad input.
  explicit TissueSimulation(const RuntimeScene& scene);
  ~TissueSimulation();
  TissueSimulation(const TissueSimulation&) = delete;
  TissueSimulation& operator=(const TissueSimulation&) = delete;

  /// Advances by the scene's time step. Status (stats.report.status): the integrator's failure
  /// if any, else the contact solver's failure, else ContactLimited when a tool's contact force
  /// was capped at its ToolSpec::max_force or a grasp slipped (the jaws let go when holding the
  /// tissue would take more than max_force; the step is then repeated from its start without
  /// that grasp), else NotConverged for an inexact solve, else Ok. A state that is not finite
  /// after the step is replaced by the state before it and the status is NonFinite.
  SimulationStepStats step();
  /// Back to the rest state, time 0, tools released.
  void reset();

  /// Tool tip pose X_ST of tool `tool` in the tissue frame (validated by the caller); ignored for
  /// a tool without contact.
  void setToolPose(int tool, const Eigen::Isometry3d& X_ST);
  /// Closes (true) or opens the tool's jaws: closing attaches the nearby surface nodes.
  void setGrasp(int tool, bool closed);
  /// Queues a blade sweep (tissue frame [m]) that the next step() applies before integrating,
  /// with the tissue moving linearly from its positions at the previous step to the current ones.
  /// The first request builds the cutter (no cut structures before). A cut that changes the
  /// topology rebuilds the masses, the model (the solver re-analyses the new pattern), the
  /// boundary conditions, the surface and the contact structures; grasps are released.
  /// An efg model keeps its DOFs: the first request replaces the surface by the surface
  /// cutter's (its vertices become mesh().nodes, without elements; tools are released), and each
  /// step with cuts runs, per sweep, the volume cut (EfgVolumeCutter on the particle motion of the
  /// last step), the surface cut (EfgSurfaceCutter on the mapped vertex motion) and the remapping
  /// of the vertices on the changed IPs; then the mapping, the body force, the boundary
  /// conditions (particles no IP with volume uses any more are fixed where they are) are rebuilt,
  /// the contact structures follow the new surface (ContactPhase::setSurface) and the solver
  /// re-analyses. A sweep a cutter rejects (it
  /// throws) keeps the positions and velocities, the model, surface and mapping follow what the
  /// cutters kept, and the step reports SolverFailed (cutError() says why). On an efg body whose
  /// cut surface has scene().efg_max_cut_triangles triangles, a sweep that would start a new cut
  /// (its box meets the surface's) is not applied and the step reports CutRefused (cutError()
  /// says why); a running cut goes on to its end.
  /// @throws std::invalid_argument for an invalid sweep or a tet scene mesh that is not tet4.
  void requestCut(const BladeSweep& sweep);
  /// Connected pieces of the tissue holding material (1 before any cut).
  int numComponents() const;
  /// Why the last step's cut failed or was refused (empty if it was not).
  const std::string& cutError() const { return cut_error_; }
  /// Per surface triangle: true on a cut (empty before any cut request; all false after an efg
  /// request that has not cut yet).
  const std::vector<bool>& cutFaces() const { return cut_faces_; }

  int numTools() const { return static_cast<int>(scene_.tools.size()); }
  const RuntimeScene& scene() const { return scene_; }
  double timeStep() const { return scene_.time_step; }
  /// The scene's tet mesh; for a body given by a closed surface (mesh.generator liver), and for an
  /// efg model after its first cut request, the surface's vertices, without elements.
  const TetMesh& mesh() const { return mesh_; }
  /// The tissue surface; its triangles index the mesh's nodes (the mapping's slots).
  const SurfaceMesh& surface() const { return surface_; }
  /// Model DOFs -> surface vertex positions (the identity on the surface nodes for a tet model,
  /// MLS weights for efg).
  const SurfaceMapping& surfaceMapping() const { return mapping_; }
  /// Surface vertex positions [m] of the current state, size 3 mesh().numNodes(), tissue frame:
  /// mapping of state().x (rest positions: mesh().nodes); entries of non-surface nodes are 0.
  const Eigen::VectorXd& surfacePositions() const { return surface_x_; }
  const SimulationState& state() const { return state_; }
  const TissueModel& model() const { return *model_; }
  /// Contact model of tool `tool` after the last step (zero when not in contact, or for a tool
  /// without contact);
  /// f0_S is the force of the tissue on the tool [N], |f0_S| <= ToolSpec::max_force.
  ContactLinearization toolContact(int tool) const;
  /// Contact force the last step applied to the tissue (ContactPhase::appliedForce) [N], size
  /// 3n, tissue frame; zero without tools. Allocates its result (diagnostics only).
  Eigen::VectorXd appliedContactForce() const;
  /// Surface vertices touched by any tool in the last step (mesh node indices, may repeat).
  const std::vector<int>& contactNodes() const { return contact_nodes_; }
  /// Structures this scene built, e.g. {"model", "integrator", "contact", "damping"}.
  std::vector<std::string> components() const;
  /// Warnings about the scene's mesh and its fixed DOFs found at construction (meshWarnings():
  /// absurd scale, pieces without a fixed node); empty for a sane scene.
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  /// Makes `model` the simulated model: body force, boundary conditions (scene regions).
  void installModel(std::unique_ptr<TissueModel> model);
  /// New contact structures on the current surface with rest positions `rest` [m] (size 3n),
  /// with the last tool poses (scene with tools only).
  std::unique_ptr<ContactPhase> makeContact(const Eigen::VectorXd& rest) const;
  /// Applies the queued cuts; returns true if the topology changed.
  bool applyCuts();
  /// applyCuts() of an efg model; throws what the cutters throw.
  bool applyEfgCuts();
  /// Builds the efg cutters on the current surface and makes the cutter's surface the scene's.
  void startEfgCutting();
  /// After an efg surface change: surface, mesh nodes, mapping, cut faces from the cutters.
  void adoptEfgSurface();
  /// After an efg model change: body force, boundary conditions (unused particles fixed where
  /// they are), solver re-analysis.
  void adoptEfgModel();
  /// Index of scene tool `tool` in the contact phase; -1 for a tool without contact or an
  /// index out of range.
  int contactIndex(int tool) const;
  /// Puts the state back to the start of the current step (x_previous_, v_previous_, time [s]).
  void restoreStart(double time);

  RuntimeScene scene_;
  /// The closed surface of a surface-generated body (the efg model's volume and the contact and
  /// rendering surface); none for a tet-mesh scene.
  std::optional<TriMesh> body_surface_;
  TetMesh original_mesh_;
  TetMesh mesh_;
  SurfaceMesh surface_;
  SurfaceMapping mapping_;
  Eigen::VectorXd surface_x_;  ///< surfacePositions() [m]
  std::unique_ptr<TissueModel> model_;
  std::unique_ptr<Integrator> integrator_;
  DynamicsProblem problem_;
  SimulationState state_;
  Eigen::VectorXd base_force_;             ///< body force [N], before contact forces
  DirichletBc base_dirichlet_;             ///< the scene's fixed DOFs, before grasps
  std::unique_ptr<ContactPhase> contact_;  ///< null for a scene without tools
  ContactPhaseSettings contact_settings_;  ///< the tools with contact, in scene order
  std::vector<int> contact_index_;         ///< per scene tool: contact phase index, or -1
  std::vector<int> contact_nodes_;
  /// Last X_ST of each contact tool (contact phase order), if any.
  std::vector<std::optional<Eigen::Isometry3d>> tool_poses_;
  std::unique_ptr<TetCutter> cutter_;  ///< null until the first cut request
  /// The efg model's volume and surface cutters; null until the first cut request on efg.
  struct EfgCutting;
  std::unique_ptr<EfgCutting> efg_cut_;
  int efg_original_vertices_ = 0;  ///< surface vertices before any efg cut (cut faces: the rest)
  std::string cut_error_;
  StepStatus cut_status_ = StepStatus::Ok;  ///< with a cut_error_: SolverFailed or CutRefused
  std::vector<BladeSweep> pending_cuts_;
  Eigen::VectorXd x_previous_;  ///< positions at the start of the last step [m]
  Eigen::VectorXd v_previous_;  ///< velocities at the start of the last step [m/s]
  std::vector<bool> cut_faces_;
  std::vector<std::string> warnings_;
};

}  // namespace surgical_sim::core
