#include "surgical_sim/core/scene/multi_body_simulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/connective/rigid_node_sampling.h"
#include "surgical_sim/core/contact/closest_point_on_segment.h"
#include "surgical_sim/core/contact/closest_point_on_triangle.h"
#include "surgical_sim/core/scene/scene_build.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::core {

namespace {

/// Rigid nodes a layer-surface vertex is skinned to (fewer if the layer has fewer).
constexpr int kSurfaceSkinNeighbours = 4;
/// Quads per edge of each hexahedron face of a poisson_disk layer's rendered surface.
constexpr int kFaceDivisions = 4;

/// "scene <path>: key '<key>': <what>".
std::invalid_argument keyError(const RuntimeScene& scene, const std::string& key,
                               const std::string& what) {
  return std::invalid_argument("scene " + scene.path + ": key '" + key + "': " + what);
}

/// Runs build(); a std::invalid_argument it throws is rethrown under key `key` of the scene.
template <class Build>
auto underKey(const RuntimeScene& scene, const std::string& key, Build build) {
  try {
    return build();
  } catch (const std::invalid_argument& e) {
    throw keyError(scene, key, e.what());
  }
}

/// Indices of the columns of `points` that lie in any of `regions`; a region that holds none is
/// an error naming `key`.fixed[k].region.
std::vector<int> pointsInRegions(const RuntimeScene& scene, const std::string& key,
                                 const Eigen::Matrix3Xd& points,
                                 const std::vector<Region>& regions) {
  std::vector<bool> held(static_cast<std::size_t>(points.cols()), false);
  for (std::size_t k = 0; k < regions.size(); ++k) {
    bool any = false;
    for (Eigen::Index i = 0; i < points.cols(); ++i)
      if (regions[k].contains(points.col(i))) any = held[static_cast<std::size_t>(i)] = true;
    if (!any)
      throw keyError(scene, key + ".fixed[" + std::to_string(k) + "].region",
                     "contains no node of '" + key + "'");
  }
  std::vector<int> out;
  for (std::size_t i = 0; i < held.size(); ++i)
    if (held[i]) out.push_back(static_cast<int>(i));
  return out;
}

/// The closed surface of a hexahedron with corner c at bits (x, y, z) of c, outward.
TriMesh hexahedronSurface(const std::vector<Eigen::Vector3d>& corners) {
  TriMesh hex;
  hex.vertices.resize(3, 8);
  for (int c = 0; c < 8; ++c) hex.vertices.col(c) = corners[static_cast<std::size_t>(c)];
  hex.triangles.resize(3, 12);
  hex.triangles << 0, 0, 1, 1, 0, 0, 2, 2, 0, 0, 4, 4,  //
      4, 6, 3, 7, 1, 5, 6, 7, 2, 3, 5, 7,               //
      6, 2, 7, 5, 5, 4, 7, 3, 3, 1, 7, 6;
  return hex;
}

/// The hexahedron's faces, each split bilinearly into kFaceDivisions^2 quads (2 triangles each).
void subdividedHexahedron(const std::vector<Eigen::Vector3d>& corners, LayerSurface& surface) {
  // Per face: corners (a, b, c, d) counter-clockwise seen from outside.
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  const int n = kFaceDivisions;
  surface.rest.resize(3, 6 * (n + 1) * (n + 1));
  surface.triangles.resize(3, 6 * 2 * n * n);
  int vertex = 0, triangle = 0;
  for (const auto& f : faces) {
    const int first = vertex;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
        const auto& P = [&](int k) { return corners[static_cast<std::size_t>(f[k])]; };
        surface.rest.col(vertex++) =
            (1 - u) * (1 - v) * P(0) + u * (1 - v) * P(1) + u * v * P(2) + (1 - u) * v * P(3);
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int a = first + j * (n + 1) + i, b = a + 1, c = b + n + 1, d = a + n + 1;
        surface.triangles.col(triangle++) << a, b, c;
        surface.triangles.col(triangle++) << a, c, d;
      }
  }
}

/// Shepard skinning of every vertex of `surface` on the layer's rest rigid nodes.
void skinSurface(const RigidNodeConfiguration& rest, LayerSurface& surface) {
  const int k = std::min(kSurfaceSkinNeighbours, rest.numNodes());
  surface.skins.assign(static_cast<std::size_t>(surface.rest.cols()), {});
  std::vector<std::pair<double, int>> distance(static_cast<std::size_t>(rest.numNodes()));
  for (Eigen::Index v = 0; v < surface.rest.cols(); ++v) {
    const Eigen::Vector3d X = surface.rest.col(v);
    for (int j = 0; j < rest.numNodes(); ++j)
      distance[static_cast<std::size_t>(j)] = {(X - rest.p_TN[static_cast<std::size_t>(j)]).norm(),
                                               j};
    std::partial_sort(distance.begin(), distance.begin() + k, distance.end());
    auto& skins = surface.skins[static_cast<std::size_t>(v)];
    const auto offset = [&](int j) {
      const auto jj = static_cast<std::size_t>(j);
      return Eigen::Vector3d(rest.q_TN[jj].conjugate() * (X - rest.p_TN[jj]));
    };
    if (distance[0].first <= 1e-9 * distance[static_cast<std::size_t>(k - 1)].first) {
      skins.push_back({distance[0].second, 1.0, offset(distance[0].second)});
      continue;
    }
    double sum = 0.0;
    for (int i = 0; i < k; ++i)
      sum += 1.0 / std::pow(distance[static_cast<std::size_t>(i)].first, 2);
    for (int i = 0; i < k; ++i) {
      const auto& [d, j] = distance[static_cast<std::size_t>(i)];
      skins.push_back({j, 1.0 / (d * d) / sum, offset(j)});
    }
  }
}

/// Smallest distance [m] from p to the triangles of surface.
double distanceToSurface(const LayerSurface& surface, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t)
    best = std::min(best, closestPointOnTriangle(surface.rest.col(surface.triangles(0, t)),
                                                 surface.rest.col(surface.triangles(1, t)),
                                                 surface.rest.col(surface.triangles(2, t)), p)
                              .distance_squared);
  return std::sqrt(best);
}

}  // namespace

/// A tool's pose, jaws and last contact model.
struct MultiBodySimulation::Tool {
  std::optional<Eigen::Isometry3d> X_ST;
  bool jaws_closed = false;
  /// Grasped (body, node) and the node's position in the tool frame at closing [m].
  std::vector<std::pair<int, int>> grasped;
  std::vector<Eigen::Vector3d> grasp_offsets;
  double stiffness = 0.0;  ///< per spring [N/m]
  ContactLinearization contact;
  Eigen::Vector3d grasp_force = Eigen::Vector3d::Zero();  ///< of the grasp springs on the tool [N]
};

MultiBodySimulation::MultiBodySimulation(const RuntimeScene& scene) : scene_(scene) {
  if (scene_.bodies.empty())
    throw keyError(scene_, "bodies", "a multi-body scene needs at least one body");
  std::vector<CoupledOrgan> organs(scene_.bodies.size());
  std::vector<std::vector<bool>> taken;  // per body node: fixed or attached
  for (std::size_t b = 0; b < scene_.bodies.size(); ++b) {
    const BodySpec& body = scene_.bodies[b];
    const std::string key = "bodies[" + std::to_string(b) + "]";
    TetMesh mesh = underKey(
        scene_, key, [&] { return buildSceneMesh(body.mesh, body.resolution, ElementType::Tet4); });
    organs[b].fixed_nodes = pointsInRegions(scene_, key, mesh.nodes, body.fixed);
    mesh.nodes = body.pose * mesh.nodes;
    organs_.push_back(
        underKey(scene_, key, [&] { return makeTissueModel(body.model, mesh, body.material); }));
    surfaces_.push_back(extractSurface(mesh));
    taken.emplace_back(static_cast<std::size_t>(mesh.numNodes()), false);
    for (const int a : organs[b].fixed_nodes) taken.back()[static_cast<std::size_t>(a)] = true;
    meshes_.push_back(std::move(mesh));
    organs[b].model = organs_.back().get();
  }

  std::vector<CoupledLayer> layers(scene_.connective.size());
  std::vector<OrganLayerAttachment> attachments;
  for (std::size_t l = 0; l < scene_.connective.size(); ++l) {
    const ConnectiveSpec& spec = scene_.connective[l];
    const std::string key = "connective[" + std::to_string(l) + "]";
    LayerSurface surface;
    const RigidNodeLayout layout = underKey(scene_, key, [&] {
      if (spec.sampling == "tet_mesh") {
        const TetMesh mesh = buildSceneMesh(spec.mesh, spec.resolution, ElementType::Tet4);
        surface.rest = mesh.nodes;
        surface.triangles = extractSurface(mesh).triangles;
        return tetMeshLayout(mesh, spec.material);
      }
      subdividedHexahedron(spec.hexahedron, surface);
      std::mt19937 rng(static_cast<std::mt19937::result_type>(spec.seed));
      return poissonDiskLayout(hexahedronSurface(spec.hexahedron), spec.node_spacing,
                               spec.sample_spacing, spec.neighbours, spec.material, rng);
    });
    layers_.push_back(std::make_unique<RigidNodeModel>(layout.rest, layout.samples));
    layers[l].model = layers_.back().get();
    Eigen::Matrix3Xd rest_nodes(3, layout.rest.numNodes());
    for (int j = 0; j < layout.rest.numNodes(); ++j)
      rest_nodes.col(j) = layout.rest.p_TN[static_cast<std::size_t>(j)];
    layers[l].fixed_nodes = pointsInRegions(scene_, key, rest_nodes, spec.fixed);
    skinSurface(layout.rest, surface);

    for (std::size_t k = 0; k < spec.attachments.size(); ++k) {
      const AttachmentSpec& a = spec.attachments[k];
      OrganLayerAttachment attachment;
      attachment.organ = a.body;
      attachment.layer = static_cast<int>(l);
      attachment.neighbours = a.neighbours;
      const auto b = static_cast<std::size_t>(a.body);
      for (const int node : surfaces_[b].nodes) {
        if (taken[b][static_cast<std::size_t>(node)] ||
            distanceToSurface(surface, meshes_[b].nodes.col(node)) > a.distance)
          continue;
        taken[b][static_cast<std::size_t>(node)] = true;
        attachment.nodes.push_back(node);
      }
      if (attachment.nodes.empty())
        throw keyError(scene_, key + ".attachments[" + std::to_string(k) + "]",
                       "no free surface node of body '" + scene_.bodies[b].name + "' lies within " +
                           std::to_string(a.distance) + " m of the layer");
      attachments.push_back(std::move(attachment));
    }
    layer_surfaces_.push_back(std::move(surface));
  }
  coupling_ = underKey(scene_, "connective", [&] {
    return std::make_unique<ConnectiveCoupling>(organs, layers, attachments);
  });
  solver_settings_.mass_damping = scene_.damping_mass;
  solver_settings_.stiffness_damping = scene_.damping_stiffness;
  rest_ = coupling_->restState();
  tools_.resize(scene_.tools.size());
  for (std::size_t t = 0; t < scene_.tools.size(); ++t) {
    const ToolSpec& spec = scene_.tools[t];
    tools_[t].stiffness = spec.contact == ContactResponse::Proxy ? spec.proxy_stiffness.value_or(0)
                                                                 : spec.coupling_stiffness;
  }
  reset();
}

MultiBodySimulation::~MultiBodySimulation() = default;

void MultiBodySimulation::reset() {
  state_ = rest_;
  solver_ = std::make_unique<CoupledSolver>(*coupling_, solver_settings_);
  for (Tool& tool : tools_) {
    const double stiffness = tool.stiffness;
    tool = Tool{};
    tool.stiffness = stiffness;
  }
  contact_nodes_.assign(meshes_.size(), {});
}

void MultiBodySimulation::setToolPose(int tool, const Eigen::Isometry3d& X_ST) {
  if (tool < 0 || tool >= numTools())
    throw std::invalid_argument("tool = " + std::to_string(tool) + " out of range [0, " +
                                std::to_string(numTools()) + ")");
  const Eigen::Matrix3d R = X_ST.linear();
  if (!X_ST.matrix().allFinite())
    throw std::invalid_argument("tool " + scene_.tools[tool].name + " pose is not finite");
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 ||
      R.determinant() < 0.0)
    throw std::invalid_argument("tool " + scene_.tools[tool].name +
                                " pose: the linear part is not a rotation");
  if (X_ST.translation().norm() > 1e3)
    throw std::invalid_argument("tool " + scene_.tools[tool].name +
                                " pose: tip farther than 1000 m from the origin");
  if (scene_.tools[tool].contact) tools_[tool].X_ST = X_ST;
}

void MultiBodySimulation::setGrasp(int tool, bool closed) {
  if (tool < 0 || tool >= numTools()) return;
  Tool& t = tools_[tool];
  const ToolSpec& spec = scene_.tools[tool];
  if (!closed || !spec.grasp) {
    t.jaws_closed = false;
    t.grasped.clear();
    t.grasp_offsets.clear();
    return;
  }
  if (t.jaws_closed) return;
  t.jaws_closed = true;
  if (!t.X_ST) return;
  const Eigen::Isometry3d X_TS = t.X_ST->inverse();
  for (int b = 0; b < numBodies(); ++b) {
    const auto& fixed = coupling_->organ(b).fixed_nodes;
    for (const int a : surfaces_[b].nodes) {
      const Eigen::Vector3d x = state_.organ_positions[b].segment<3>(3 * a);
      if ((x - t.X_ST->translation()).norm() > spec.grasp->radius ||
          std::find(fixed.begin(), fixed.end(), a) != fixed.end())
        continue;
      t.grasped.emplace_back(b, a);
      t.grasp_offsets.push_back(X_TS * x);
    }
  }
}

void MultiBodySimulation::addContactSprings(bool& limited) {
  for (std::size_t i = 0; i < tools_.size(); ++i) {
    const Tool& tool = tools_[i];
    const ToolSpec& spec = scene_.tools[i];
    if (!tool.X_ST || !spec.contact) continue;
    const Eigen::Vector3d tip = tool.X_ST->translation();
    const Eigen::Vector3d end = tip - spec.shaft_length * tool.X_ST->linear().col(2);
    const std::size_t first = loads_.springs.size();
    Eigen::Vector3d push = Eigen::Vector3d::Zero();  // summed spring force on the tissue [N]
    for (int b = 0; b < numBodies(); ++b)
      for (const int a : surfaces_[b].nodes) {
        // Grasped nodes follow the jaws, not the capsule.
        if (std::find(tool.grasped.begin(), tool.grasped.end(), std::make_pair(b, a)) !=
            tool.grasped.end())
          continue;
        const Eigen::Vector3d x = state_.organ_positions[b].segment<3>(3 * a);
        const SegmentPointClosest c = closestPointOnSegment(tip, end, x);
        if (c.distance_squared >= spec.radius * spec.radius) continue;
        const double d = std::sqrt(c.distance_squared);
        const Eigen::Vector3d n = d > 1e-12 * spec.radius
                                      ? Eigen::Vector3d((x - c.point) / d)
                                      : Eigen::Vector3d(tool.X_ST->linear().col(0));
        const Eigen::Vector3d target = c.point + spec.radius * n;
        loads_.springs.push_back(CoupledSpring{b, a, target, tool.stiffness});
        spring_tool_.push_back(static_cast<int>(i));
        spring_normal_.push_back(n);
        push += tool.stiffness * (target - x);
        contact_nodes_[static_cast<std::size_t>(b)].push_back(a);
      }
    if (push.norm() > spec.max_force) {
      limited = true;
      const double scale = spec.max_force / push.norm();
      for (std::size_t s = first; s < loads_.springs.size(); ++s)
        loads_.springs[s].stiffness *= scale;
    }
  }
}

void MultiBodySimulation::addGraspSprings() {
  for (std::size_t i = 0; i < tools_.size(); ++i) {
    const Tool& tool = tools_[i];
    if (!tool.X_ST) continue;
    for (std::size_t g = 0; g < tool.grasped.size(); ++g) {
      const auto [b, a] = tool.grasped[g];
      loads_.springs.push_back(
          CoupledSpring{b, a, *tool.X_ST * tool.grasp_offsets[g], tool.stiffness});
      spring_tool_.push_back(static_cast<int>(i));
      spring_normal_.emplace_back();
    }
  }
}

void MultiBodySimulation::measureTools() {
  for (std::size_t i = 0; i < tools_.size(); ++i) {
    Tool& tool = tools_[i];
    tool.contact = ContactLinearization{};
    tool.grasp_force.setZero();
    if (tool.X_ST) tool.contact.p0_S = tool.X_ST->translation();
  }
  for (std::size_t s = 0; s < loads_.springs.size(); ++s) {
    const CoupledSpring& spring = loads_.springs[s];
    Tool& tool = tools_[static_cast<std::size_t>(spring_tool_[s])];
    const Eigen::Vector3d x = state_.organ_positions[spring.organ].segment<3>(3 * spring.node);
    ContactLinearization& c = tool.contact;
    if (const auto& n = spring_normal_[s]) {
      const double compression = n->dot(spring.target - x);
      if (compression <= 0.0) continue;  // the node left the capsule: no push
      c.f0_S -= spring.stiffness * compression * *n;
      c.K_S -= spring.stiffness * *n * n->transpose();
    } else {
      const Eigen::Vector3d f = spring.stiffness * (x - spring.target);
      c.f0_S += f;
      tool.grasp_force += f;
      c.K_S -= spring.stiffness * Eigen::Matrix3d::Identity();
    }
    ++c.contacts;
    c.in_contact = true;
  }
}

SimulationStepStats MultiBodySimulation::step() {
  Stopwatch watch;
  SimulationStepStats stats;
  start_ = state_;
  bool limited = false;
  for (int attempt = 0; attempt < 2; ++attempt) {
    loads_.gravity = scene_.gravity;
    loads_.springs.clear();
    spring_tool_.clear();
    spring_normal_.clear();
    for (auto& nodes : contact_nodes_) nodes.clear();
    Stopwatch collision;
    addContactSprings(limited);
    addGraspSprings();
    stats.collision_seconds = collision.seconds();
    Stopwatch integrate;
    stats.report = solver_->step(loads_, scene_.time_step, state_);
    stats.integrate_seconds = integrate.seconds();
    measureTools();
    if (stats.report.status != StepStatus::Ok) break;
    // Jaws that would hold more than max_force slip: the step again without their grasp.
    bool slipped = false;
    for (std::size_t i = 0; i < tools_.size(); ++i) {
      Tool& tool = tools_[i];
      if (tool.grasped.empty() || tool.grasp_force.norm() <= scene_.tools[i].max_force) continue;
      tool.grasped.clear();
      tool.grasp_offsets.clear();
      slipped = true;
    }
    if (!slipped) break;
    limited = true;
    state_ = start_;
  }
  if (stats.report.status == StepStatus::Ok && limited)
    stats.report.status = StepStatus::ContactLimited;
  for (const Tool& tool : tools_) stats.contacts += tool.contact.contacts;
  stats.step_seconds = watch.seconds();
  return stats;
}

ContactLinearization MultiBodySimulation::toolContact(int tool) const {
  if (tool < 0 || tool >= numTools()) return {};
  return tools_[tool].contact;
}

Eigen::Matrix3Xd MultiBodySimulation::layerSurfacePositions(int layer) const {
  const LayerSurface& surface = layer_surfaces_[layer];
  const RigidNodeConfiguration& q = state_.layer_configurations[layer];
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, surface.rest.cols());
  for (Eigen::Index v = 0; v < x.cols(); ++v)
    for (const LayerSurface::Skin& s : surface.skins[static_cast<std::size_t>(v)]) {
      const auto j = static_cast<std::size_t>(s.node);
      x.col(v) += s.weight * (q.p_TN[j] + q.q_TN[j] * s.offset);
    }
  return x;
}

std::vector<std::string> MultiBodySimulation::components() const {
  std::vector<std::string> out = {"coupling", "solver"};
  if (scene_.damping_mass > 0.0 || scene_.damping_stiffness > 0.0) out.emplace_back("damping");
  const auto any = [&](auto predicate) {
    return std::any_of(scene_.tools.begin(), scene_.tools.end(), predicate);
  };
  if (any([](const ToolSpec& t) { return t.contact.has_value(); })) out.emplace_back("contact");
  if (any([](const ToolSpec& t) { return t.grasp.has_value(); })) out.emplace_back("grasp");
  return out;
}

}  // namespace surgical_sim::core
