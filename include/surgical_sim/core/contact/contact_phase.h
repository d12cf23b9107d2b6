#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <vector>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/contact/contact_detector.h"
#include "surgical_sim/core/contact/contact_point.h"
#include "surgical_sim/core/contact/contact_solver.h"
#include "surgical_sim/core/contact/grasp_constraint.h"
#include "surgical_sim/core/contact/proxy_contact.h"
#include "surgical_sim/core/contact/surface_bvh.h"
#include "surgical_sim/core/contact/tool_capsule.h"
#include "surgical_sim/core/mesh/surface.h"
#include "surgical_sim/core/solve/dynamics_problem.h"
#include "surgical_sim/core/solve/integrator.h"
#include "surgical_sim/core/tissue/surface_mapping.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// How a tool's contact is answered.
enum class ContactResponse {
  Constraint,  ///< unilateral constraints through the step compliance (ContactSolver)
  Proxy,       ///< god-object proxy spring (ProxyContact)
};

/// One tool of a scene. Physical parameters have no defaults (NaN fails validation).
struct ToolSettings {
  double radius = std::numeric_limits<double>::quiet_NaN();        ///< [m], > 0
  double shaft_length = std::numeric_limits<double>::quiet_NaN();  ///< [m], >= 0
  ContactResponse response = ContactResponse::Constraint;
  double proxy_stiffness = std::numeric_limits<double>::quiet_NaN();  ///< Proxy only [N/m], > 0
  std::optional<double> grasp_radius;  ///< [m], > 0; nullopt: the tool has no jaws
  /// Constraint only: tool body to commanded pose spring k_c [N/m], > 0 (ToolCoupling).
  double coupling_stiffness = std::numeric_limits<double>::quiet_NaN();
  /// Constraint only: damper in parallel with the coupling spring [N s/m], >= 0 (ToolCoupling).
  double coupling_damping = 0.0;
  /// Cap on the tool's contact force (constraint multipliers, proxy spring) and on its grasp
  /// force (the grasp slips above it) [N], > 0.
  double max_force = std::numeric_limits<double>::quiet_NaN();
};

/// Settings of the contact phase.
struct ContactPhaseSettings {
  std::vector<ToolSettings> tools;  ///< at least one
  ContactDetectorSettings detector;
  ContactSolverSettings solver;
};

/// Wall time of the contact phase of the last step [ms]. contact_ms = compliance_ms + lcp_ms +
/// linearization_ms (up to clock reads).
struct ContactTimings {
  double collision_ms = 0.0;  ///< BVH refit + narrow phase (detection)
  double contact_ms = 0.0;    ///< constraint solve / proxy update, correction, linearization
  /// Step-compliance solves inside the constraint solve (Integrator::applyStepCompliance: the
  /// Delassus columns, the carried force and the correction).
  double compliance_ms = 0.0;
  long compliance_solves = 0;  ///< number of those solves
  /// The rest of the constraint solve: gaps, W from the compliance columns, the LCP, the force
  /// caps and the correction update.
  double lcp_ms = 0.0;
  double linearization_ms = 0.0;  ///< proxies and the per-tool contact linearizations
};

/// Contact facade used by the simulator; construct it only when the scene has tools (a tool-less
/// scene builds nothing and its contact phase costs zero). Per step:
///   contact.setToolPose(i, X_ST); contact.setGrasp(i, closed);        // inputs, any time
///   contact.prepareStep(state.x, f_base, bc_base, problem.external_force, problem.dirichlet);
///   integrator.step(problem, dt, state);                               // free motion
///   if (contact.slipOverloadedGrasps(model, state.x, failed)) {        // a grasp let go:
///     restore state; prepareStep again; integrator.step again;        //   redo the step
///   }
///   contact.finishStep(integrator, model, dt, state);                  // detect, solve, correct
///   contact.linearization(i), contact.timings()                        // outputs
/// All quantities in the tissue frame S. Contacts are detected on the surface vertices
/// (positions SurfaceMapping::apply of the model's) and act on the model through the mapping.
/// prepareStep/finishStep never throw and allocate nothing
/// in steady state (buffers grow only when more contacts or grasped nodes appear than before).
class ContactPhase {
 public:
  /// @param surface the tissue surface (its triangles index the mapping's slots)
  /// @param mapping the model's surface mapping: model positions -> vertex positions, and
  ///        contact, proxy and grasp forces back to the model's DOFs
  /// @param rest model rest positions [m], size 3 mapping.numNodes(), in S (BVH construction)
  /// @param update_velocity false for quasi-static integrators
  /// @throws std::invalid_argument naming "contact.tools" (empty), "tool.*" (coupling_stiffness
  ///         is checked for constraint tools only), "contact.*", or "contact.rest" when rest
  ///         does not have the mapping's size
  ContactPhase(const SurfaceMesh& surface, SurfaceMapping mapping, const Eigen::VectorXd& rest,
               const ContactPhaseSettings& settings, bool update_velocity);

  /// A cut changed the surface and its mapping onto the same model nodes: afterwards the phase
  /// is as a new one on them (grasps released, proxies, carried force and contacts cleared), with
  /// the tool poses kept. The BVH keeps the leaves of the unchanged triangles
  /// (SurfaceBvh::setTriangles at the vertex positions of model positions x [m]) instead of being
  /// built anew.
  /// @throws std::invalid_argument when mapping has another node count or x another size
  ///         ("contact.mapping", "contact.x"), or for a triangle index out of range
  ///         ("bvh.triangles"); nothing changes then
  void setSurface(const SurfaceMesh& surface, SurfaceMapping mapping, const Eigen::VectorXd& x);
  int numTools() const { return static_cast<int>(tools_.size()); }
  /// Sets tool `tool`'s tip pose X_ST. Returns false (pose kept) for a bad index or NaN/Inf.
  /// A tool whose pose was never set touches and grasps nothing.
  bool setToolPose(int tool, const Eigen::Isometry3d& X_ST);
  /// Requests the jaws of tool `tool` closed or open (applied at the next prepareStep). A grasp
  /// that slipped stays released until the jaws are opened and closed again.
  void setGrasp(int tool, bool closed);

  /// Before Integrator::step: updates grasps at positions x; writes
  /// external_force = base_force + carried constraint force + proxy forces and
  /// dirichlet = base_dirichlet + grasped nodes at their targets.
  void prepareStep(const Eigen::VectorXd& x, const Eigen::VectorXd& base_force,
                   const DirichletBc& base_dirichlet, Eigen::VectorXd& external_force,
                   DirichletBc& dirichlet);
  /// After Integrator::step, before finishStep: the jaws of a grasping tool slip (the grasp is
  /// released) when the force of the tissue on them at positions x [m] (size 3n), the sum of
  /// the internal forces on the grasped nodes, exceeds the tool's max_force, or when
  /// step_failed (the integrator could not take the step with the grasps). Returns whether a
  /// grasp slipped: the caller then restores the state from before the step and repeats
  /// prepareStep and the integrator step (nothing else of the contact phase has changed since
  /// prepareStep). Never throws.
  bool slipOverloadedGrasps(const TissueModel& model, const Eigen::VectorXd& x, bool step_failed);
  /// After Integrator::step (state = free motion): refits the BVH, detects, solves the
  /// constraints and corrects state, updates proxies and the per-tool linearizations.
  /// Returns the contact solver's status (Ok when no constraint tool touches), ContactLimited
  /// also when a proxy spring force was capped.
  StepStatus finishStep(Integrator& integrator, const TissueModel& model, double dt,
                        SimulationState& state);

  const ContactLinearization& linearization(int tool) const;
  const ContactTimings& timings() const { return timings_; }
  /// Contacts of the constraint tools found in the last step.
  const std::vector<ContactPoint>& contacts() const { return contacts_; }
  const SurfaceMapping& mapping() const { return mapping_; }
  const ContactSolver& solver() const { return solver_; }
  /// Contact force the last step applied to the tissue [N], size 3n, S: the proxy spring
  /// forces of its free step plus the constraint force H^T lambda that replaced the carried one
  /// (grasp reactions excluded). Allocates its result (diagnostics only).
  Eigen::VectorXd appliedForce() const;

 private:
  struct Tool {
    ToolCapsule capsule;
    ContactResponse response;
    std::optional<ProxyContact> proxy;
    std::optional<GraspConstraint> grasp;  ///< none for a tool without jaws
    bool grasp_requested = false;
    bool posed = false;    ///< a pose was set: until then the tool touches and grasps nothing
    bool slipped = false;  ///< the grasp slipped; cleared when the jaws open
    double max_force;      ///< [N]
    ContactLinearization linearization;
    bool grasping() const { return grasp && grasp->active(); }
  };

  /// The tools as the settings give them: no pose, jaws open, no proxy contact.
  static std::vector<Tool> makeTools(const ContactPhaseSettings& settings);

  ContactPhaseSettings settings_;
  Eigen::Matrix3Xi triangles_;
  SurfaceMapping mapping_;
  Eigen::VectorXd surface_x_;  ///< vertex positions [m], 3 mapping_.numSlots()
  bool update_velocity_;
  SurfaceBvh bvh_;
  ContactDetector detector_;
  ContactSolver solver_;
  std::vector<Tool> tools_;
  std::vector<ContactPoint> contacts_;
  std::vector<std::uint8_t> fixed_mask_;
  Eigen::VectorXd applied_force_;   ///< constraint force applied in the current free step [N]
  Eigen::VectorXd proxy_force_;     ///< proxy forces applied in the current free step [N]
  Eigen::VectorXd internal_force_;  ///< work vector for grasp forces [N]
  ContactTimings timings_;
};

}  // namespace surgical_sim::core
