#include "surgical_sim/core/scene/tissue_simulation.h"

#include <future>
#include <numeric>
#include <stdexcept>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/contact/contact_phase.h"
#include "surgical_sim/core/cutting/cut_tissue_model.h"
#include "surgical_sim/core/mesh/mesh_check.h"
#include "surgical_sim/core/scene/scene_build.h"
#include "surgical_sim/core/tissue/efg_model.h"
#include "surgical_sim/core/tissue/model_factory.h"
#include "surgical_sim/core/tissue/surface_mapping.h"

namespace surgical_sim::core {
namespace {

bool isFailure(StepStatus s) {
  return s == StepStatus::SolverFailed || s == StepStatus::NonFinite || s == StepStatus::BlowUp;
}

/// Status of a step from the integrator's and the contact phase's: a failure first, then a
/// capped contact, then an inexact solve.
StepStatus combined(StepStatus integrator, StepStatus contact) {
  if (isFailure(integrator)) return integrator;
  if (isFailure(contact)) return contact;
  for (const StepStatus s : {StepStatus::ContactLimited, StepStatus::NotConverged}) {
    if (integrator == s || contact == s) return s;
  }
  return StepStatus::Ok;
}

/// Cutting splits the mesh's tets; a meshless model cannot be cut yet.
std::invalid_argument efgCutError(const std::string& path) {
  return std::invalid_argument("scene " + path +
                               ": key 'blades': cutting needs a tet model; model efg cannot be "
                               "cut (remove 'blades' or choose a tet model)");
}

}  // namespace

TissueSimulation::TissueSimulation(const RuntimeScene& scene) : scene_(scene) {
  if (scene_.model == ModelKind::Efg && !scene_.blades.empty()) throw efgCutError(scene_.path);
  if (isSurfaceGenerator(scene_.mesh.generator)) {
    if (scene_.model != ModelKind::Efg) {
      throw std::invalid_argument("scene " + scene_.path +
                                  ": key 'model': " + modelName(scene_.model) +
                                  " needs a tet mesh; a closed surface body needs model efg");
    }
    body_surface_ = buildSceneSurface(scene_.mesh, scene_.resolution);
    original_mesh_.nodes = body_surface_->vertices;
    original_mesh_.elements.resize(4, 0);
  } else {
    original_mesh_ = buildSceneMesh(scene_.mesh, scene_.resolution, scene_.element_type);
    requireValidMesh(original_mesh_);
  }

  integrator_ =
      makeSceneIntegrator(scene_, scene_.integrator, scene_.solver, scene_.newton_tolerance);
  problem_.damping.mass_coefficient = scene_.damping_mass;
  problem_.damping.stiffness_coefficient = scene_.damping_stiffness;
  contact_settings_.solver.max_iterations = 500;
  contact_settings_.solver.relative_tolerance = 1e-6;
  contact_settings_.solver.full_delassus = scene_.contact_full_delassus;
  for (const ToolSpec& t : scene_.tools) {
    if (!t.contact) {
      contact_index_.push_back(-1);
      continue;
    }
    contact_index_.push_back(static_cast<int>(contact_settings_.tools.size()));
    ToolSettings tool;
    tool.radius = t.radius;
    tool.shaft_length = t.shaft_length;
    tool.response = *t.contact;
    if (t.proxy_stiffness) tool.proxy_stiffness = *t.proxy_stiffness;
    if (t.grasp) tool.grasp_radius = t.grasp->radius;
    tool.coupling_stiffness = t.coupling_stiffness;
    tool.coupling_damping = t.coupling_damping;
    tool.max_force = t.max_force;
    contact_settings_.tools.push_back(tool);
  }
  reset();
  warnings_ = meshWarnings(original_mesh_, base_dirichlet_.dofs);
}

void TissueSimulation::installModel(std::unique_ptr<TissueModel> model) {
  model_ = std::move(model);
  problem_.model = model_.get();
  base_force_ = model_->bodyForce(scene_.gravity);
  problem_.external_force = base_force_;
  base_dirichlet_ = fixedDirichlet(scene_, model_->restPositions());
  problem_.dirichlet = base_dirichlet_;
}

std::unique_ptr<ContactPhase> TissueSimulation::makeContact(const Eigen::VectorXd& rest) const {
  auto contact = std::make_unique<ContactPhase>(surface_, mapping_, rest, contact_settings_,
                                                scene_.integrator != IntegratorKind::QuasiStatic);
  for (std::size_t i = 0; i < tool_poses_.size(); ++i)
    if (tool_poses_[i]) contact->setToolPose(static_cast<int>(i), *tool_poses_[i]);
  return contact;
}

TissueSimulation::~TissueSimulation() = default;

void TissueSimulation::reset() {
  // Back to the uncut scene: the original mesh and model, no cut structures.
  cutter_.reset();
  pending_cuts_.clear();
  cut_faces_.clear();
  mesh_ = original_mesh_;
  if (body_surface_) {
    surface_.triangles = body_surface_->triangles;
    surface_.nodes.resize(static_cast<std::size_t>(mesh_.numNodes()));
    std::iota(surface_.nodes.begin(), surface_.nodes.end(), 0);
    installModel(std::make_unique<EfgModel>(*body_surface_, scene_.material, scene_.efg));
  } else {
    surface_ = extractSurface(mesh_);
    installModel(makeTissueModel(scene_.model, mesh_, scene_.material, scene_.efg));
  }
  mapping_ = makeSurfaceMapping(*model_, mesh_, surface_);
  state_.x = model_->restPositions();
  mapping_.apply(state_.x, surface_x_);
  state_.v = Eigen::VectorXd::Zero(state_.x.size());
  state_.time = 0.0;
  x_previous_ = state_.x;
  contact_nodes_.clear();
  integrator_->reset();
  // A fresh contact phase: no carried constraint force, proxy or grasp survives a reset, so a
  // replay after reset is bit-identical to the first run.
  tool_poses_.assign(contact_settings_.tools.size(), std::nullopt);
  contact_.reset();
  if (!contact_settings_.tools.empty()) contact_ = makeContact(model_->restPositions());
}

int TissueSimulation::contactIndex(int tool) const {
  return tool >= 0 && tool < numTools() ? contact_index_[static_cast<std::size_t>(tool)] : -1;
}

void TissueSimulation::setToolPose(int tool, const Eigen::Isometry3d& X_ST) {
  const int c = contactIndex(tool);
  if (c < 0) return;
  tool_poses_[static_cast<std::size_t>(c)] = X_ST;
  contact_->setToolPose(c, X_ST);
}

void TissueSimulation::setGrasp(int tool, bool closed) {
  const int c = contactIndex(tool);
  if (c >= 0) contact_->setGrasp(c, closed);
}

void TissueSimulation::requestCut(const BladeSweep& sweep) {
  if (scene_.model == ModelKind::Efg) throw efgCutError(scene_.path);
  validateBladeSweep(sweep);
  if (!cutter_) cutter_ = std::make_unique<TetCutter>(mesh_, scene_.material.density);
  pending_cuts_.push_back(sweep);
}

bool TissueSimulation::applyCuts() {
  bool changed = false;
  for (const BladeSweep& sweep : pending_cuts_) {
    if (!cutter_->cut(sweep, x_previous_, state_.x).topology_changed) continue;
    changed = true;
    state_.x = cutter_->transfer(state_.x);
    state_.v = cutter_->transfer(state_.v);
    x_previous_ = cutter_->transfer(x_previous_);
  }
  pending_cuts_.clear();
  if (!changed) return false;
  mesh_ = cutter_->mesh();
  surface_ = cutter_->surface();
  cut_faces_ = cutter_->cutFaces();
  // The contact structures depend only on the surface, its mapping (a cut tet model's DOFs are
  // the cutter's nodes: the selection) and the rest positions: built on a second thread while
  // the model is built.
  mapping_ = SurfaceMapping::selection(mesh_.numNodes(), surface_.nodes);
  const Eigen::VectorXd rest =
      Eigen::Map<const Eigen::VectorXd>(mesh_.nodes.data(), 3 * mesh_.numNodes());
  std::future<std::unique_ptr<ContactPhase>> contact;
  if (!contact_settings_.tools.empty())
    contact = std::async(std::launch::async, [this, &rest] { return makeContact(rest); });
  installModel(makeCutTissueModel(scene_.model, *cutter_, scene_.material));
  integrator_->reset();  // new stiffness pattern: the linear solver re-analyses it
  if (contact.valid()) contact_ = contact.get();
  return true;
}

SimulationStepStats TissueSimulation::step() {
  SimulationStepStats stats;
  Stopwatch step_watch;
  if (!pending_cuts_.empty()) {
    Stopwatch cut_watch;
    stats.topology_changed = applyCuts();
    stats.cut_seconds = cut_watch.seconds();
  }
  x_previous_ = state_.x;
  v_previous_ = state_.v;
  const double time_previous = state_.time;
  if (contact_)
    contact_->prepareStep(state_.x, base_force_, base_dirichlet_, problem_.external_force,
                          problem_.dirichlet);
  Stopwatch phase;
  stats.report = integrator_->step(problem_, scene_.time_step, state_);
  bool slipped = false;
  if (contact_ &&
      contact_->slipOverloadedGrasps(*model_, state_.x, isFailure(stats.report.status))) {
    // The jaws let go: the step again from its start, without the slipped grasps.
    slipped = true;
    restoreStart(time_previous);
    contact_->prepareStep(state_.x, base_force_, base_dirichlet_, problem_.external_force,
                          problem_.dirichlet);
    stats.report = integrator_->step(problem_, scene_.time_step, state_);
  }
  stats.integrate_seconds = phase.seconds();
  if (contact_) {
    const StepStatus s = contact_->finishStep(*integrator_, *model_, scene_.time_step, state_);
    stats.report.status =
        combined(stats.report.status, slipped ? combined(s, StepStatus::ContactLimited) : s);
    stats.collision_seconds = 1e-3 * contact_->timings().collision_ms;
    stats.contact_seconds = 1e-3 * contact_->timings().contact_ms;
    stats.contact_timings = contact_->timings();
    stats.contacts = static_cast<int>(contact_->contacts().size());
    contact_nodes_.clear();
    for (const ContactPoint& c : contact_->contacts())
      for (int k = 0; k < 3; ++k) contact_nodes_.push_back(c.nodes[k]);
  }
  if (!state_.x.allFinite() || !state_.v.allFinite()) {
    restoreStart(time_previous);
    stats.report.status = StepStatus::NonFinite;
  }
  mapping_.apply(state_.x, surface_x_);
  stats.step_seconds = step_watch.seconds();
  return stats;
}

void TissueSimulation::restoreStart(double time) {
  state_.x = x_previous_;
  state_.v = v_previous_;
  state_.time = time;
}

Eigen::VectorXd TissueSimulation::appliedContactForce() const {
  return contact_ ? contact_->appliedForce() : Eigen::VectorXd::Zero(state_.x.size());
}

ContactLinearization TissueSimulation::toolContact(int tool) const {
  const int c = contactIndex(tool);
  if (c < 0) return {};
  return contact_->linearization(c);
}

std::vector<std::string> TissueSimulation::components() const {
  std::vector<std::string> c = {"mesh", "model:" + model_->name(),
                                "integrator:" + integrator_->name()};
  if (problem_.damping.active()) c.push_back("damping");
  if (contact_) c.push_back("contact");
  if (cutter_) c.push_back("cutting");
  return c;
}

}  // namespace surgical_sim::core
