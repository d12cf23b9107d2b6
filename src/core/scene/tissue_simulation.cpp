#include "surgical_sim/core/scene/tissue_simulation.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <future>
#include <numeric>
#include <stdexcept>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/contact/contact_phase.h"
#include "surgical_sim/core/cutting/cut_tissue_model.h"
#include "surgical_sim/core/cutting/efg_surface_cutter.h"
#include "surgical_sim/core/cutting/efg_volume_cutter.h"
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
  for (const StepStatus s :
       {StepStatus::ContactLimited, StepStatus::CutRefused, StepStatus::NotConverged}) {
    if (integrator == s || contact == s) return s;
  }
  return StepStatus::Ok;
}

/// Vertex positions of `mapping` at model positions x [m], 3 x slots.
Eigen::Matrix3Xd vertexPositions(const SurfaceMapping& mapping, const Eigen::VectorXd& x) {
  Eigen::VectorXd flat;
  mapping.apply(x, flat);
  return Eigen::Map<const Eigen::Matrix3Xd>(flat.data(), 3, mapping.numSlots());
}

/// True when the box of `sweep` meets that of the positions `start` and `end` [m] of the
/// vertices `used`.
bool sweepMeetsSurface(const BladeSweep& sweep, const std::vector<int>& used,
                       const Eigen::Ref<const Eigen::Matrix3Xd>& start,
                       const Eigen::Ref<const Eigen::Matrix3Xd>& end) {
  Eigen::AlignedBox3d box;
  for (int v : used) {
    box.extend(start.col(v));
    box.extend(end.col(v));
  }
  return box.intersects(sweepBox(sweep));
}

}  // namespace

struct TissueSimulation::EfgCutting {
  EfgCutting(EfgModel& model, const Eigen::VectorXd& x, const TriMesh& surface,
             const EfgSurfaceCutOptions& options)
      : source(model, x), volume(model), surface(surface, source, options) {}
  EfgModelSource source;
  EfgVolumeCutter volume;
  EfgSurfaceCutter surface;
};

TissueSimulation::TissueSimulation(const RuntimeScene& scene) : scene_(scene) {
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
  efg_cut_.reset();
  cut_error_.clear();
  cut_status_ = StepStatus::Ok;
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
  validateBladeSweep(sweep);
  if (scene_.model == ModelKind::Efg) {
    if (!efg_cut_) startEfgCutting();
  } else if (!cutter_) {
    cutter_ = std::make_unique<TetCutter>(mesh_, scene_.material.density);
  }
  pending_cuts_.push_back(sweep);
}

int TissueSimulation::numComponents() const {
  if (efg_cut_) return efg_cut_->volume.pieces();
  return cutter_ ? cutter_->numComponents() : 1;
}

void TissueSimulation::startEfgCutting() {
  // The surface's used vertices, compacted: the surface cutter's vertex ids.
  std::vector<int> id(static_cast<std::size_t>(mesh_.numNodes()), -1);
  TriMesh surface;
  surface.triangles.resize(3, surface_.triangles.cols());
  std::vector<int> used;
  for (Eigen::Index t = 0; t < surface_.triangles.cols(); ++t)
    for (int c = 0; c < 3; ++c) {
      int& v = id[static_cast<std::size_t>(surface_.triangles(c, t))];
      if (v < 0) {
        v = static_cast<int>(used.size());
        used.push_back(surface_.triangles(c, t));
      }
      surface.triangles(c, t) = v;
    }
  surface.vertices.resize(3, static_cast<Eigen::Index>(used.size()));
  for (std::size_t v = 0; v < used.size(); ++v)
    surface.vertices.col(static_cast<Eigen::Index>(v)) = mesh_.nodes.col(used[v]);
  EfgSurfaceCutOptions options;
  options.front_width = scene_.efg.spacing;
  options.tolerance = 1e-9 * scene_.efg.spacing;  // the volume cutter's contact distance
  efg_cut_ =
      std::make_unique<EfgCutting>(dynamic_cast<EfgModel&>(*model_), state_.x, surface, options);
  efg_original_vertices_ = static_cast<int>(used.size());
  adoptEfgSurface();
  // Contact structures on the new vertex slots: grasps are released.
  if (!contact_settings_.tools.empty()) contact_ = makeContact(model_->restPositions());
}

void TissueSimulation::adoptEfgSurface() {
  const EfgSurfaceCutter& cutter = efg_cut_->surface;
  surface_.triangles = cutter.triangles();
  surface_.nodes.clear();
  for (int v = 0; v < cutter.numVertices(); ++v)
    if (cutter.vertexUsed(v)) surface_.nodes.push_back(v);
  mesh_.nodes = cutter.restVertices();
  mesh_.elements.resize(4, 0);
  mapping_ = cutter.mapping(model_->numNodes());
  mapping_.apply(state_.x, surface_x_);
  cut_faces_.assign(static_cast<std::size_t>(surface_.triangles.cols()), false);
  for (Eigen::Index t = 0; t < surface_.triangles.cols(); ++t)
    cut_faces_[static_cast<std::size_t>(t)] =
        (surface_.triangles.col(t).array() >= efg_original_vertices_).all();
}

void TissueSimulation::adoptEfgModel() {
  base_force_ = model_->bodyForce(scene_.gravity);
  problem_.external_force = base_force_;
  // The scene's fixed DOFs and, fixed where they are, the particles without material.
  DirichletBc bc = fixedDirichlet(scene_, model_->restPositions());
  std::vector<char> fixed(static_cast<std::size_t>(state_.x.size()), 0);
  for (int d : bc.dofs) fixed[static_cast<std::size_t>(d)] = 1;
  std::vector<std::pair<int, double>> dofs;
  for (std::size_t k = 0; k < bc.dofs.size(); ++k) dofs.emplace_back(bc.dofs[k], bc.positions[k]);
  for (int p : efg_cut_->volume.unusedParticles())
    for (int c = 0; c < 3; ++c) {
      const int d = 3 * p + c;
      state_.v[d] = 0.0;
      if (!fixed[static_cast<std::size_t>(d)]) dofs.emplace_back(d, state_.x[d]);
    }
  std::sort(dofs.begin(), dofs.end());
  base_dirichlet_.dofs.resize(dofs.size());
  base_dirichlet_.positions.resize(static_cast<Eigen::Index>(dofs.size()));
  for (std::size_t k = 0; k < dofs.size(); ++k) {
    base_dirichlet_.dofs[k] = dofs[k].first;
    base_dirichlet_.positions[static_cast<Eigen::Index>(k)] = dofs[k].second;
  }
  problem_.dirichlet = base_dirichlet_;
  integrator_->modelChanged();  // same DOFs: the solver keeps what the changed pattern allows
}

bool TissueSimulation::applyEfgCuts() {
  bool surface_changed = false;
  bool model_changed = false;
  for (const BladeSweep& sweep : pending_cuts_) {
    // Vertex motion over the last step with the mapping before this sweep (surface_x_ is the
    // mapping at state_.x: the last step and adoptEfgSurface keep it so).
    const Eigen::Matrix3Xd start = vertexPositions(mapping_, x_previous_);
    const Eigen::Map<const Eigen::Matrix3Xd> end(surface_x_.data(), 3, mapping_.numSlots());
    const int triangles = efg_cut_->surface.numTriangles();
    if (!efg_cut_->surface.cutActive() && triangles >= scene_.efg_max_cut_triangles &&
        sweepMeetsSurface(sweep, surface_.nodes, start, end)) {
      cut_error_ = "cut refused: the cut surface has " + std::to_string(triangles) +
                   " triangles, at its budget efg.max_cut_triangles = " +
                   std::to_string(scene_.efg_max_cut_triangles) +
                   "; no new cut starts (the sweep was not applied)";
      cut_status_ = StepStatus::CutRefused;
      continue;
    }
    const EfgCutResult volume = efg_cut_->volume.cut(sweep, x_previous_, state_.x);
    const EfgParticleMotion motion{x_previous_, state_.x, volume.changed_ips};
    const EfgSurfaceCutStep surface = efg_cut_->surface.cut(sweep, start, end, &motion);
    bool remapped = !surface.remapped.empty();
    if (!volume.changed_ips.empty())
      remapped = !efg_cut_->surface.remapVerticesOfIps(volume.changed_ips).empty() || remapped;
    model_changed = model_changed || !volume.changed_ips.empty();
    if (remapped || surface.crossed_edges > 0) {
      surface_changed = true;
      adoptEfgSurface();
    }
  }
  if (model_changed) adoptEfgModel();
  const bool changed = surface_changed || model_changed;
  // The contact phase follows the new surface; its BVH keeps the unchanged triangles' leaves.
  if (changed && contact_) contact_->setSurface(surface_, mapping_, state_.x);
  return changed;
}

bool TissueSimulation::applyCuts() {
  if (efg_cut_) {
    bool changed = true;
    try {
      changed = applyEfgCuts();
    } catch (const std::exception& e) {
      // The cutters keep a consistent model and surface after a rejected cut: follow them.
      cut_error_ = std::string("cut rejected: ") + e.what();
      cut_status_ = StepStatus::SolverFailed;
      adoptEfgSurface();
      adoptEfgModel();
      if (!contact_settings_.tools.empty()) contact_ = makeContact(model_->restPositions());
    }
    pending_cuts_.clear();
    return changed;
  }
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
    cut_error_.clear();
    cut_status_ = StepStatus::Ok;
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
  if (!cut_error_.empty()) stats.report.status = combined(stats.report.status, cut_status_);
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
  if (cutter_ || efg_cut_) c.push_back("cutting");
  return c;
}

}  // namespace surgical_sim::core
