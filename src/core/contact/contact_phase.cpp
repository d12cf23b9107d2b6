#include "surgical_sim/core/contact/contact_phase.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/solve/dirichlet_projection.h"

namespace surgical_sim::core {
namespace {

/// BVH leaf inflation as a fraction of the mean surface edge length [-].
constexpr double kFatMarginPerEdge = 0.1;

double meanEdgeLength(const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& x) {
  double sum = 0.0;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      sum +=
          (x.segment<3>(3 * triangles(k, t)) - x.segment<3>(3 * triangles((k + 1) % 3, t))).norm();
    }
  }
  return triangles.cols() > 0 ? sum / (3.0 * static_cast<double>(triangles.cols())) : 0.0;
}

/// The solver's coupling of each tool; a proxy tool has no constraint contacts, its spring is its
/// coupling.
std::vector<ToolCoupling> toolCouplings(const ContactPhaseSettings& settings) {
  std::vector<ToolCoupling> couplings;
  for (const ToolSettings& tool : settings.tools) {
    const bool proxy = tool.response == ContactResponse::Proxy;
    if (proxy) requirePositive("tool.proxy_stiffness", tool.proxy_stiffness, "N/m");
    couplings.push_back({proxy ? tool.proxy_stiffness : tool.coupling_stiffness, tool.max_force,
                         proxy ? 0.0 : tool.coupling_damping});
  }
  return couplings;
}

/// The vertex positions of model positions x [m] ("contact.<name>" in the error when x does not
/// have the mapping's size).
Eigen::VectorXd mappedPositions(const SurfaceMapping& mapping, const Eigen::VectorXd& x,
                                const std::string& name) {
  if (x.size() != 3 * mapping.numNodes()) {
    throw std::invalid_argument("contact." + name + ": " + std::to_string(x.size()) +
                                " coordinates for a surface mapping of " +
                                std::to_string(mapping.numNodes()) + " model nodes");
  }
  Eigen::VectorXd x_s;
  mapping.apply(x, x_s);
  return x_s;
}

int checkedToolCount(const ContactPhaseSettings& settings) {
  if (settings.tools.empty()) {
    throw std::invalid_argument(
        "contact.tools: a contact phase needs at least one tool (build none for a tool-less "
        "scene)");
  }
  return static_cast<int>(settings.tools.size());
}

/// The constraint solver of the settings' tools, with no force carried yet.
ContactSolver makeSolver(const ContactPhaseSettings& settings) {
  return ContactSolver(settings.solver, checkedToolCount(settings) * settings.detector.max_contacts,
                       toolCouplings(settings));
}

}  // namespace

ContactPhase::ContactPhase(const SurfaceMesh& surface, SurfaceMapping mapping,
                           const Eigen::VectorXd& rest, const ContactPhaseSettings& settings,
                           bool update_velocity)
    : settings_(settings),
      triangles_(surface.triangles),
      mapping_(std::move(mapping)),
      surface_x_(mappedPositions(mapping_, rest, "rest")),
      update_velocity_(update_velocity),
      bvh_(surface.triangles, surface_x_,
           kFatMarginPerEdge * meanEdgeLength(surface.triangles, surface_x_)),
      detector_(settings.detector),
      solver_(makeSolver(settings)),
      tools_(makeTools(settings)) {
  contacts_.reserve(static_cast<size_t>(numTools() * settings.detector.max_contacts));
  fixed_mask_.assign(static_cast<size_t>(rest.size()), 0);
  applied_force_.setZero(rest.size());
  proxy_force_.setZero(rest.size());
  internal_force_.setZero(rest.size());
}

std::vector<ContactPhase::Tool> ContactPhase::makeTools(const ContactPhaseSettings& settings) {
  std::vector<Tool> tools;
  for (const ToolSettings& tool : settings.tools) {
    Tool entry{
        ToolCapsule(tool.radius, tool.shaft_length),
        tool.response,
        std::nullopt,
        tool.grasp_radius ? std::optional<GraspConstraint>(*tool.grasp_radius) : std::nullopt,
        false,
        false,
        false,
        tool.max_force,
        ContactLinearization()};
    if (tool.response == ContactResponse::Proxy) {
      entry.proxy.emplace(tool.proxy_stiffness, tool.max_force);
    }
    tools.push_back(std::move(entry));
  }
  return tools;
}

void ContactPhase::setSurface(const SurfaceMesh& surface, SurfaceMapping mapping,
                              const Eigen::VectorXd& x) {
  if (mapping.numNodes() != mapping_.numNodes()) {
    throw std::invalid_argument("contact.mapping: " + std::to_string(mapping.numNodes()) +
                                " model nodes, the contact phase has " +
                                std::to_string(mapping_.numNodes()));
  }
  Eigen::VectorXd surface_x = mappedPositions(mapping, x, "x");
  bvh_.setTriangles(surface.triangles, surface_x);
  triangles_ = surface.triangles;
  mapping_ = std::move(mapping);
  surface_x_ = std::move(surface_x);
  solver_ = makeSolver(settings_);
  std::vector<Tool> tools = makeTools(settings_);
  for (std::size_t t = 0; t < tools.size(); ++t) {
    tools[t].capsule = tools_[t].capsule;
    tools[t].posed = tools_[t].posed;
  }
  tools_ = std::move(tools);
  contacts_.clear();
  applied_force_.setZero();
  proxy_force_.setZero();
}

bool ContactPhase::setToolPose(int tool, const Eigen::Isometry3d& X_ST) {
  if (tool < 0 || tool >= numTools()) return false;
  Tool& entry = tools_[static_cast<size_t>(tool)];
  if (!entry.capsule.setPose(X_ST)) return false;
  entry.posed = true;
  return true;
}

void ContactPhase::setGrasp(int tool, bool closed) {
  if (tool < 0 || tool >= numTools()) return;
  Tool& entry = tools_[static_cast<size_t>(tool)];
  entry.grasp_requested = closed;
  if (!closed) entry.slipped = false;
}

const ContactLinearization& ContactPhase::linearization(int tool) const {
  return tools_[static_cast<size_t>(std::clamp(tool, 0, numTools() - 1))].linearization;
}

void ContactPhase::prepareStep(const Eigen::VectorXd& x, const Eigen::VectorXd& base_force,
                               const DirichletBc& base_dirichlet, Eigen::VectorXd& external_force,
                               DirichletBc& dirichlet) {
  markDirichletDofs(base_dirichlet.dofs, fixed_mask_);
  dirichlet.dofs.assign(base_dirichlet.dofs.begin(), base_dirichlet.dofs.end());
  for (Tool& tool : tools_) {
    if (!tool.grasp) continue;
    tool.grasp->update(tool.grasp_requested && tool.posed && !tool.slipped, tool.capsule.pose(),
                       mapping_, x, fixed_mask_);
    tool.grasp->appendDofs(dirichlet.dofs);
  }
  const auto total = static_cast<Eigen::Index>(dirichlet.dofs.size());
  if (dirichlet.positions.size() != total) dirichlet.positions.resize(total);
  Eigen::Index offset = base_dirichlet.positions.size();
  dirichlet.positions.head(offset) = base_dirichlet.positions;
  for (const Tool& tool : tools_) {
    if (!tool.grasp) continue;
    tool.grasp->writeTargets(tool.capsule.pose(),
                             dirichlet.positions.segment(offset, tool.grasp->numDofs()));
    offset += tool.grasp->numDofs();
  }
  external_force = base_force;
  if (solver_.tissueForce().size() == base_force.size()) {
    applied_force_ = solver_.tissueForce();  // carried into the free step
    external_force += applied_force_;
  } else {
    applied_force_.setZero(base_force.size());
  }
  proxy_force_.setZero(base_force.size());
  for (const Tool& tool : tools_) {
    if (tool.proxy) tool.proxy->addTissueForce(mapping_, proxy_force_);
  }
  external_force += proxy_force_;
}

bool ContactPhase::slipOverloadedGrasps(const TissueModel& model, const Eigen::VectorXd& x,
                                        bool step_failed) {
  const bool grasping =
      std::any_of(tools_.begin(), tools_.end(), [](const Tool& t) { return t.grasping(); });
  if (!grasping) return false;
  if (!step_failed) {
    internal_force_.setZero();
    model.addInternalForce(x, internal_force_);
  }
  bool slipped = false;
  for (Tool& tool : tools_) {
    if (!tool.grasping()) continue;
    if (!step_failed && tool.grasp->toolForce(internal_force_).norm() <= tool.max_force) continue;
    tool.grasp->update(false, tool.capsule.pose(), mapping_, x, fixed_mask_);
    tool.slipped = true;
    slipped = true;
  }
  return slipped;
}

Eigen::VectorXd ContactPhase::appliedForce() const {
  Eigen::VectorXd force = proxy_force_;
  if (solver_.tissueForce().size() == force.size()) force += solver_.tissueForce();
  return force;
}

StepStatus ContactPhase::finishStep(Integrator& integrator, const TissueModel& model, double dt,
                                    SimulationState& state) {
  Stopwatch watch;
  mapping_.apply(state.x, surface_x_);
  bvh_.refit(surface_x_);
  contacts_.clear();
  for (size_t t = 0; t < tools_.size(); ++t) {
    if (tools_[t].posed && tools_[t].response == ContactResponse::Constraint &&
        !tools_[t].grasping()) {
      detector_.detect(static_cast<int>(t), tools_[t].capsule, triangles_, surface_x_, bvh_,
                       contacts_);
    }
  }
  timings_.collision_ms = watch.milliseconds();
  watch.restart();
  const Integrator::ComplianceUse compliance_before = integrator.complianceUse();
  StepStatus status =
      solver_.solve(integrator, mapping_, contacts_, applied_force_, dt, update_velocity_, state);
  const Integrator::ComplianceUse compliance_after = integrator.complianceUse();
  timings_.compliance_ms = 1e3 * (compliance_after.seconds - compliance_before.seconds);
  timings_.compliance_solves = compliance_after.calls - compliance_before.calls;
  timings_.lcp_ms = watch.milliseconds() - timings_.compliance_ms;
  const Stopwatch linearization_watch;
  // The proxies follow the corrected surface.
  if (std::any_of(tools_.begin(), tools_.end(), [](const Tool& t) { return t.proxy && t.posed; }))
    mapping_.apply(state.x, surface_x_);
  bool grasping = false;
  for (size_t t = 0; t < tools_.size(); ++t) {
    Tool& tool = tools_[t];
    if (tool.proxy && !tool.posed) continue;
    if (tool.proxy) {
      tool.proxy->update(tool.capsule.tip(), tool.capsule.radius(), triangles_, surface_x_, bvh_);
      tool.linearization = tool.proxy->linearization();
      if (tool.proxy->limited() &&
          (status == StepStatus::Ok || status == StepStatus::NotConverged)) {
        status = StepStatus::ContactLimited;
      }
    } else {
      solver_.linearize(static_cast<int>(t), tool.capsule.tip(), tool.linearization);
    }
    grasping = grasping || tool.grasping();
  }
  if (grasping) {
    internal_force_.setZero();
    model.addInternalForce(state.x, internal_force_);
    for (Tool& tool : tools_) {
      if (!tool.grasping()) continue;
      tool.linearization.in_contact = true;
      tool.linearization.f0_S += tool.grasp->toolForce(internal_force_);
    }
  }
  timings_.linearization_ms = linearization_watch.milliseconds();
  timings_.contact_ms = watch.milliseconds();
  return status;
}

}  // namespace surgical_sim::core
