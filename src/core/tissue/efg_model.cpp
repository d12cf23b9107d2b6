#include "surgical_sim/core/tissue/efg_model.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "surgical_sim/core/tissue/efg_shape_functions.h"
#include "surgical_sim/core/tissue/point_stiffness.h"
#include "surgical_sim/core/tissue/signed_svd.h"

namespace surgical_sim::core {
namespace {

// Compile-time neighbour count K (8) or Eigen::Dynamic (up to EfgOptions::kMaxNeighbours).
constexpr int maxNeighbours(int K) { return K == Eigen::Dynamic ? EfgOptions::kMaxNeighbours : K; }
constexpr int dofs(int K) { return K == Eigen::Dynamic ? Eigen::Dynamic : 3 * K; }

template <int K>
using NodeMatrix = Eigen::Matrix<double, 3, K, Eigen::ColMajor, 3, maxNeighbours(K)>;
template <int K>
using GradientMap =
    Eigen::Map<const Eigen::Matrix<double, K, 3, Eigen::ColMajor, maxNeighbours(K), 3>>;
template <int K>
using ElementMatrix = Eigen::Matrix<double, dofs(K), dofs(K), Eigen::ColMajor, 3 * maxNeighbours(K),
                                    3 * maxNeighbours(K)>;

// The positions (or any 3-vectors) of the k nodes `nodes` as columns.
template <int K>
NodeMatrix<K> gather(const Eigen::VectorXd& v, const int* nodes, int k) {
  NodeMatrix<K> ve(3, k);
  for (int a = 0; a < k; ++a) ve.col(a) = v.segment<3>(3 * nodes[a]);
  return ve;
}

template <int K>
void scatter(const NodeMatrix<K>& fe, const int* nodes, Eigen::VectorXd& f) {
  for (int a = 0; a < fe.cols(); ++a) f.segment<3>(3 * nodes[a]) += fe.col(a);
}

// Group g's stabilisation matrix (k x k) in a bucket's stabilisation sums.
template <int K>
Eigen::Map<const Eigen::Matrix<double, K, K>> groupStabilization(const std::vector<double>& sums,
                                                                 int g, int k) {
  return {sums.data() + static_cast<size_t>(k) * k * g, k, k};
}

// The stabilisation of group g of `bucket` at node positions xe (rest positions in `rest`): with
// u = xe - X, fe -= S u (per node) when fe is non-null and *energy += 1/2 sum_a u_a . (S u)_a
// when energy is non-null.
template <int K, typename Bucket>
void addGroupStabilization(const Bucket& bucket, int g, const NodeMatrix<K>& xe,
                           const Eigen::VectorXd& rest, NodeMatrix<K>* fe, double* energy) {
  const int k = bucket.k;
  const NodeMatrix<K> ue = xe - gather<K>(rest, bucket.groupNodes(g), k);
  const NodeMatrix<K> su = ue * groupStabilization<K>(bucket.stabilization, g, k);
  if (fe != nullptr) *fe -= su;
  if (energy != nullptr) *energy += 0.5 * su.cwiseProduct(ue).sum();
}

template <int K>
using RankVector = Eigen::Matrix<double, dofs(K), 1, Eigen::ColMajor, 3 * maxNeighbours(K), 1>;

// The fixed-R tangent R K0 R^T of isotropic linear elasticity summed over the points of a group,
// from L = sum_p w_p vec(H_p) vec(H_p)^T with H_p = R_p grad_p^T (3 x k, vec: entry 3 a + i =
// H(i, a)). Per point, block (a, b) is w (mu (h_a . h_b) I + mu h_b h_a^T + lambda h_a h_b^T),
// so the sum is Ke_ab = lambda L_ab + mu L_ba + mu tr(L_ab) I (L_ab: the 3 x 3 block of L).
template <int K>
void rotatedLinearStiffness(const ElementMatrix<K>& L, double mu, double lambda,
                            ElementMatrix<K>& Ke) {
  const Eigen::Index k = L.rows() / 3;
  for (Eigen::Index a = 0; a < k; ++a) {
    for (Eigen::Index b = 0; b < k; ++b) {
      const auto Lab = L.template block<3, 3>(3 * a, 3 * b);
      Ke.template block<3, 3>(3 * a, 3 * b) =
          lambda * Lab + mu * L.template block<3, 3>(3 * b, 3 * a);
      Ke.template block<3, 3>(3 * a, 3 * b).diagonal().array() += mu * Lab.trace();
    }
  }
}

}  // namespace

struct EfgModel::IpShape {
  Eigen::VectorXd phi;
  Eigen::MatrixXd grad;      ///< k x 3 [1/m]
  Eigen::MatrixXd matching;  ///< k x 3 [1/m]
  Eigen::VectorXd detours;   ///< k [m]
  double support = 0.0;      ///< [m]
};

EfgModel::EfgModel(const TetMesh& mesh, const Material& material, const EfgOptions& options)
    : EfgModel(buildEfgGrid(mesh, options), material, options) {}

EfgModel::EfgModel(const TriMesh& surface, const Material& material, const EfgOptions& options)
    : EfgModel(buildEfgGrid(surface, options), material, options) {}

EfgModel::EfgModel(EfgGrid grid, const Material& material, const EfgOptions& options)
    : options_(options),
      law_(Material::validated(material)),
      mu_(material.mu()),
      lambda_(material.lambda()),
      density_(material.density),
      grid_(std::move(grid)) {
  const int n = static_cast<int>(grid_.particles.cols());
  const int m = static_cast<int>(grid_.integration_points.cols());
  const int k = options.neighbours;
  // Canonical order, so that IPs with the same particles have identical sets.
  for (int e = 0; e < m; ++e)
    std::sort(grid_.neighbours.col(e).begin(), grid_.neighbours.col(e).end());
  rest_positions_ = Eigen::Map<const Eigen::VectorXd>(grid_.particles.data(), 3 * n);
  body_weight_ = Eigen::VectorXd::Zero(n);
  lumped_mass_ = Eigen::VectorXd::Zero(3 * n);
  ip_particles_.resize(static_cast<size_t>(m));
  slot_.resize(static_cast<size_t>(m));
  slot_capacity_.assign(static_cast<size_t>(m), k);
  support_.resize(static_cast<size_t>(m));
  for (int e = 0; e < m; ++e) slot_[static_cast<size_t>(e)] = static_cast<size_t>(e) * k;
  shape_values_.resize(static_cast<size_t>(m) * k);
  detours_.assign(static_cast<size_t>(m) * k, 0.0);
  gradients_.resize(static_cast<size_t>(m) * k * 3);
  matching_.resize(static_cast<size_t>(m) * k * 3);
  const Eigen::VectorXd no_detours = Eigen::VectorXd::Zero(k);
  for (int e = 0; e < m; ++e) {
    std::vector<int> particles(grid_.neighbours.col(e).begin(), grid_.neighbours.col(e).end());
    const IpShape shape = computeIp(e, particles, no_detours);
    storeIp(e, std::move(particles), shape);
    addIpMass(e, 1.0);
  }
  buckets_.resize(EfgOptions::kMaxNeighbours + 1);
  for (int size = 0; size <= EfgOptions::kMaxNeighbours; ++size) {
    buckets_[static_cast<size_t>(size)].k = size;
    buckets_[static_cast<size_t>(size)].scatter =
        BlockScatterMap(Eigen::SparseMatrix<double>(), Eigen::MatrixXi(size, 0));
  }
  std::vector<int> all(static_cast<size_t>(m));
  std::iota(all.begin(), all.end(), 0);
  joinGroups(all);
}

EfgModel::IpShape EfgModel::computeIp(int e, const std::vector<int>& particles,
                                      const Eigen::VectorXd& detours) const {
  const int k = static_cast<int>(particles.size());
  const Eigen::Vector3d x_e = grid_.integration_points.col(e);
  Eigen::Matrix3Xd points(3, k);
  for (int a = 0; a < k; ++a)
    points.col(a) = grid_.particles.col(particles[static_cast<size_t>(a)]);
  const Eigen::Matrix3Xd rel = points.colwise() - x_e;
  IpShape out;
  out.detours = detours;
  const Eigen::VectorXd r = rel.colwise().norm().transpose() + detours;  // kernel distances [m]
  out.support = options_.kernel_support * r.maxCoeff();
  const MlsShapeFunctions mls = computeMlsShapeFunctions(x_e, points, out.support, detours);
  if (mls.status != MlsStatus::Ok) {
    throw std::invalid_argument("EfgModel: integration point " + std::to_string(e) + " at (" +
                                std::to_string(x_e.x()) + ", " + std::to_string(x_e.y()) + ", " +
                                std::to_string(x_e.z()) + ") m with " + std::to_string(k) +
                                " particles: MLS moment matrix " + toString(mls.status) +
                                " (check efg.neighbours and efg.kernel_support)");
  }
  out.phi = mls.phi;
  out.grad = mls.grad;
  // Shape matching: kernel weights, weighted centroid and the normalised moments.
  Eigen::VectorXd w(k);
  for (int a = 0; a < k; ++a) w(a) = quarticSplineKernel(r(a) / out.support);
  w /= w.sum();
  const Eigen::Matrix3Xd q = points.colwise() - points * w;
  const double moment = (q * w.asDiagonal() * q.transpose()).trace() / 3.0;  // [m^2]
  out.matching = (q * w.asDiagonal()).transpose() / moment;
  return out;
}

void EfgModel::storeIp(int e, std::vector<int> particles, const IpShape& shape) {
  const size_t ie = static_cast<size_t>(e);
  const int k = static_cast<int>(particles.size());
  if (k > slot_capacity_[ie]) {
    slot_[ie] = shape_values_.size();
    slot_capacity_[ie] = k;
    shape_values_.resize(shape_values_.size() + k);
    detours_.resize(detours_.size() + k);
    gradients_.resize(gradients_.size() + 3 * k);
    matching_.resize(matching_.size() + 3 * k);
  }
  const size_t slot = slot_[ie];
  Eigen::Map<Eigen::VectorXd>(shape_values_.data() + slot, k) = shape.phi;
  Eigen::Map<Eigen::VectorXd>(detours_.data() + slot, k) = shape.detours;
  Eigen::Map<Eigen::MatrixXd>(gradients_.data() + 3 * slot, k, 3) = shape.grad;
  Eigen::Map<Eigen::MatrixXd>(matching_.data() + 3 * slot, k, 3) = shape.matching;
  support_[ie] = shape.support;
  ip_particles_[ie] = std::move(particles);
}

Eigen::MatrixXd EfgModel::ipStabilization(int e) const {
  const std::vector<int>& particles = ipParticles(e);
  const Eigen::Index k = static_cast<Eigen::Index>(particles.size());
  Eigen::MatrixXd rel(k, 3);  // X_a - X_e
  for (Eigen::Index a = 0; a < k; ++a) {
    rel.row(a) =
        (grid_.particles.col(particles[static_cast<size_t>(a)]) - grid_.integration_points.col(e))
            .transpose();
  }
  Eigen::MatrixXd C = Eigen::MatrixXd::Identity(k, k);
  C.rowwise() -= shapeValues(e).transpose();
  C.noalias() -= rel * shapeGradients(e).transpose();
  const double scale =
      2.0 * options_.stabilization * mu_ * grid_.volumes(e) / rel.squaredNorm();  // [N/m]
  return scale * (C.transpose() * C);
}

void EfgModel::addIpStabilization(int e, GroupBucket& b, int g, double sign) const {
  if (options_.stabilization == 0.0) return;
  const int k = b.k;
  Eigen::Map<Eigen::MatrixXd>(b.stabilization.data() + static_cast<size_t>(k) * k * g, k, k) +=
      sign * ipStabilization(e);
}

void EfgModel::addIpMass(int e, double sign) {
  const std::vector<int>& particles = ipParticles(e);
  const Eigen::Map<const Eigen::VectorXd> phi = shapeValues(e);
  const double mass = sign * density_ * grid_.volumes(e);  // [kg]
  const double phi2 = phi.squaredNorm();
  for (size_t a = 0; a < particles.size(); ++a) {
    const int node = particles[a];
    const double phi_a = phi(static_cast<Eigen::Index>(a));
    body_weight_(node) += mass * phi_a;
    lumped_mass_.segment<3>(3 * node).array() += mass * phi_a * phi_a / phi2;
  }
}

void EfgModel::setNeighbourhoods(const std::vector<EfgNeighbourhood>& changes) {
  const int n = static_cast<int>(grid_.particles.cols());
  const int m = numIntegrationPoints();
  std::vector<char> seen(static_cast<size_t>(m), 0);
  std::vector<std::pair<std::vector<int>, IpShape>> shapes;
  shapes.reserve(changes.size());
  for (const EfgNeighbourhood& c : changes) {
    const auto fail = [&](const std::string& what) {
      throw std::invalid_argument("EfgModel::setNeighbourhoods: integration point " +
                                  std::to_string(c.ip) + ": " + what);
    };
    if (c.ip < 0 || c.ip >= m) fail("index out of range [0, " + std::to_string(m) + ")");
    if (seen[static_cast<size_t>(c.ip)]++ != 0) fail("listed twice");
    const int k = static_cast<int>(c.particles.size());
    if (k < 4 || k > EfgOptions::kMaxNeighbours) {
      fail(std::to_string(k) + " particles: must be in [4, " +
           std::to_string(EfgOptions::kMaxNeighbours) + "]");
    }
    if (!c.distances.empty() && static_cast<int>(c.distances.size()) != k)
      fail("distances has " + std::to_string(c.distances.size()) + " entries, particles " +
           std::to_string(k));
    if (!std::isfinite(c.volume) || c.volume < 0.0)
      fail("volume " + std::to_string(c.volume) + " m^3: must be finite and >= 0");
    std::vector<int> order(static_cast<size_t>(k));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return c.particles[static_cast<size_t>(a)] < c.particles[static_cast<size_t>(b)];
    });
    std::vector<int> particles(static_cast<size_t>(k));
    Eigen::VectorXd detours = Eigen::VectorXd::Zero(k);
    for (int a = 0; a < k; ++a) {
      const size_t src = static_cast<size_t>(order[static_cast<size_t>(a)]);
      const int p = c.particles[src];
      if (p < 0 || p >= n) fail("particle " + std::to_string(p) + " out of range");
      if (a > 0 && particles[static_cast<size_t>(a) - 1] == p)
        fail("particle " + std::to_string(p) + " repeated");
      particles[static_cast<size_t>(a)] = p;
      if (c.distances.empty()) continue;
      const double euclidean = (grid_.particles.col(p) - grid_.integration_points.col(c.ip)).norm();
      const double r = c.distances[src];
      if (!std::isfinite(r) || r < euclidean * (1.0 - 1e-12))
        fail("distance " + std::to_string(r) + " m of particle " + std::to_string(p) +
             ": must be finite and >= its Euclidean distance " + std::to_string(euclidean) + " m");
      detours(a) = std::max(0.0, r - euclidean);
    }
    IpShape shape = computeIp(c.ip, particles, detours);
    shapes.emplace_back(std::move(particles), std::move(shape));
  }
  std::vector<int> ips;
  for (size_t i = 0; i < changes.size(); ++i) {
    const int e = changes[i].ip;
    ips.push_back(e);
    leaveGroup(e);
    addIpMass(e, -1.0);
    grid_.volumes(e) = changes[i].volume;
    storeIp(e, std::move(shapes[i].first), shapes[i].second);
    addIpMass(e, 1.0);
  }
  joinGroups(ips);
}

size_t EfgModel::ParticleSetHash::operator()(const std::vector<int>& particles) const {
  size_t h = particles.size();
  for (int p : particles) h = h * 0x9e3779b97f4a7c15ULL + static_cast<size_t>(p);
  return h;
}

void EfgModel::leaveGroup(int e) {
  const std::vector<int>& particles = ipParticles(e);
  GroupBucket& b = buckets_[particles.size()];
  const auto found = group_of_set_.find(particles);
  const int g = found->second;
  std::vector<int>& members = b.members[static_cast<size_t>(g)];
  members.erase(std::find(members.begin(), members.end(), e));
  if (!members.empty()) {
    addIpStabilization(e, b, g, -1.0);
    return;
  }
  // The last group takes the empty group's index.
  group_of_set_.erase(found);
  const int last = b.groups() - 1;
  if (g != last) {
    std::copy(b.groupNodes(last), b.groupNodes(last) + b.k,
              b.nodes.begin() + static_cast<std::ptrdiff_t>(b.k) * g);
    b.members[static_cast<size_t>(g)] = std::move(b.members.back());
    group_of_set_[ipParticles(b.members[static_cast<size_t>(g)].front())] = g;
    const size_t block = static_cast<size_t>(b.k) * b.k;
    std::copy(b.stabilization.end() - static_cast<std::ptrdiff_t>(block), b.stabilization.end(),
              b.stabilization.begin() + static_cast<std::ptrdiff_t>(block) * g);
  }
  b.scatter.removeGroup(g);
  b.members.pop_back();
  b.nodes.resize(b.nodes.size() - static_cast<size_t>(b.k));
  b.stabilization.resize(b.stabilization.size() - static_cast<size_t>(b.k) * b.k);
}

void EfgModel::joinGroups(const std::vector<int>& ips) {
  std::vector<std::pair<int, int>> created;  // (k, group)
  for (int e : ips) {
    const std::vector<int>& particles = ipParticles(e);
    GroupBucket& b = buckets_[particles.size()];
    const auto [entry, is_new] = group_of_set_.try_emplace(particles, b.groups());
    if (is_new) {
      b.members.emplace_back();
      b.nodes.insert(b.nodes.end(), particles.begin(), particles.end());
      b.stabilization.resize(b.stabilization.size() + static_cast<size_t>(b.k) * b.k);
      created.emplace_back(b.k, entry->second);
    }
    b.members[static_cast<size_t>(entry->second)].push_back(e);
    addIpStabilization(e, b, entry->second, 1.0);
  }
  // Couple the particles of the new groups: added[i] (ascending) the particles newly coupled
  // with particle i, those its pattern column does not hold yet.
  const Eigen::SparseMatrix<double>& pattern = stiffnessPattern();
  const auto coupled = [&](int i, int j) {
    if (pattern.cols() == 0) return false;  // the model under construction
    const int* rows = pattern.innerIndexPtr();
    return std::binary_search(rows + pattern.outerIndexPtr()[3 * i],
                              rows + pattern.outerIndexPtr()[3 * i + 1], 3 * j);
  };
  std::vector<std::vector<int>> added(static_cast<size_t>(numNodes()));
  bool grown = false;
  for (const auto& [k, g] : created) {
    const int* nodes = buckets_[static_cast<size_t>(k)].groupNodes(g);
    for (int a = 0; a < k; ++a) {
      std::vector<int>& row = added[static_cast<size_t>(nodes[a])];
      for (int c = 0; c < k; ++c) {
        if (coupled(nodes[a], nodes[c])) continue;
        const auto at = std::lower_bound(row.begin(), row.end(), nodes[c]);
        if (at != row.end() && *at == nodes[c]) continue;
        row.insert(at, nodes[c]);
        grown = true;
      }
    }
  }
  if (grown) {
    growPattern(added);
    for (GroupBucket& b : buckets_) {  // the groups that have a map: all but the new ones
      b.scatter.followGrownPattern(
          Eigen::Map<const Eigen::MatrixXi>(b.nodes.data(), b.k, b.scatter.numGroups()), added);
    }
  }
  for (const auto& [k, g] : created) {
    GroupBucket& b = buckets_[static_cast<size_t>(k)];
    b.scatter.setGroup(stiffnessPattern(), g, b.groupNodes(g));
  }
}

Eigen::Map<const Eigen::VectorXd> EfgModel::shapeValues(int e) const {
  return {shape_values_.data() + slot_[static_cast<size_t>(e)],
          static_cast<Eigen::Index>(ipParticles(e).size())};
}

Eigen::Map<const Eigen::VectorXd> EfgModel::detours(int e) const {
  return {detours_.data() + slot_[static_cast<size_t>(e)],
          static_cast<Eigen::Index>(ipParticles(e).size())};
}

Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3>> EfgModel::shapeGradients(int e) const {
  return {gradients_.data() + 3 * slot_[static_cast<size_t>(e)],
          static_cast<Eigen::Index>(ipParticles(e).size()), 3};
}

void EfgModel::pointWeights(int e, const Eigen::Vector3d& X, std::vector<int>& particles,
                            std::vector<double>& weights) const {
  if (e < 0 || e >= numIntegrationPoints()) {
    throw std::invalid_argument("EfgModel::pointWeights: ip = " + std::to_string(e) +
                                " out of range [0, " + std::to_string(numIntegrationPoints()) +
                                ")");
  }
  particles = ipParticles(e);
  const Eigen::Index k = static_cast<Eigen::Index>(particles.size());
  Eigen::Matrix3Xd points(3, k);
  for (Eigen::Index a = 0; a < k; ++a)
    points.col(a) = grid_.particles.col(particles[static_cast<size_t>(a)]);
  MlsShapeFunctions mls =
      computeMlsShapeFunctions(X, points, support_[static_cast<size_t>(e)], detours(e));
  if (mls.status == MlsStatus::IllConditioned) {
    // X lies beyond the kernels of most of the set: a support reaching it from every particle
    // (kernel distance |X - X_a| + detour_a) still reproduces linear fields, so X stays where it
    // rests, where the IP's own weights would put it at the IP.
    const Eigen::VectorXd r = (points.colwise() - X).colwise().norm().transpose() + detours(e);
    mls = computeMlsShapeFunctions(X, points, options_.kernel_support * r.maxCoeff(), detours(e));
  }
  const Eigen::VectorXd phi = mls.status == MlsStatus::Ok ? mls.phi : shapeValues(e);
  weights.assign(phi.data(), phi.data() + k);
}

Eigen::SparseMatrix<double> EfgModel::interpolation(const Eigen::Matrix3Xd& points) const {
  std::vector<Eigen::Triplet<double>> triplets;
  std::vector<int> particles;
  std::vector<double> weights;
  for (int i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d p = points.col(i);
    const Eigen::Vector3d cell = ((p - grid_.origin) / grid_.spacing).array().floor();
    int e = -1;
    if (cell.allFinite() && (cell.array() >= 0.0).all() &&
        (cell.array() < grid_.cells.cast<double>().array()).all()) {
      const Eigen::Vector3i c = cell.cast<int>();
      e = grid_.ip_of_cell[static_cast<size_t>(c.x() + grid_.cells.x() *
                                                           (c.y() + grid_.cells.y() * c.z()))];
    }
    if (e < 0) {
      (grid_.integration_points.colwise() - p).colwise().squaredNorm().minCoeff(&e);
    }
    pointWeights(e, p, particles, weights);
    for (size_t a = 0; a < particles.size(); ++a)
      triplets.emplace_back(i, particles[a], weights[a]);
  }
  Eigen::SparseMatrix<double> W(points.cols(), grid_.particles.cols());
  W.setFromTriplets(triplets.begin(), triplets.end());
  return W;
}

Eigen::VectorXd EfgModel::bodyForce(const Eigen::Vector3d& a) const {
  Eigen::VectorXd f(rest_positions_.size());
  for (Eigen::Index i = 0; i < body_weight_.size(); ++i) f.segment<3>(3 * i) = body_weight_(i) * a;
  return f;
}

template <typename Nodes>
Eigen::Matrix3d EfgModel::matchingRotation(const Nodes& xe, int e) const {
  const Eigen::Map<const Eigen::MatrixXd> weights(
      matching_.data() + 3 * slot_[static_cast<size_t>(e)], xe.cols(), 3);
  return computeSignedRotation(xe * weights);
}

Eigen::Matrix3d EfgModel::rotatedStress(const Eigen::Matrix3d& F, const Eigen::Matrix3d& R) const {
  const Eigen::Matrix3d G = R.transpose() * F;
  const Eigen::Matrix3d eps = 0.5 * (G + G.transpose()) - Eigen::Matrix3d::Identity();
  return R * (2.0 * mu_ * eps + lambda_ * eps.trace() * Eigen::Matrix3d::Identity());
}

double EfgModel::matchingEnergyDensity(const Eigen::Matrix3d& F, const Eigen::Matrix3d& R) const {
  const Eigen::Matrix3d RtF = R.transpose() * F;
  const Eigen::Matrix3d eps = 0.5 * (RtF + RtF.transpose()) - Eigen::Matrix3d::Identity();
  return mu_ * eps.squaredNorm() + 0.5 * lambda_ * eps.trace() * eps.trace();
}

template <typename Body>
void EfgModel::forEachBucket(Body&& body) const {
  for (const GroupBucket& bucket : buckets_) {
    if (bucket.groups() == 0) continue;
    if (bucket.k == 8) {
      body(bucket, std::integral_constant<int, 8>());
    } else {
      body(bucket, std::integral_constant<int, Eigen::Dynamic>());
    }
  }
}

template <int K>
double EfgModel::energyImpl(const GroupBucket& bucket, const Eigen::VectorXd& x) const {
  const int k = bucket.k;
  double energy = 0.0;
  for (int g = 0; g < bucket.groups(); ++g) {
    const NodeMatrix<K> xe = gather<K>(x, bucket.groupNodes(g), k);
    for (const int e : bucket.members[static_cast<size_t>(g)]) {
      const GradientMap<K> G(gradients_.data() + 3 * slot_[e], k, 3);
      const Eigen::Matrix3d F = xe * G;
      const double psi = options_.rotation == EfgRotation::Polar
                             ? law_.energyDensity(F)
                             : matchingEnergyDensity(F, matchingRotation(xe, e));
      energy += grid_.volumes(e) * psi;
    }
    if (options_.stabilization > 0.0) {
      addGroupStabilization<K>(bucket, g, xe, rest_positions_, nullptr, &energy);
    }
  }
  return energy;
}

template <int K>
void EfgModel::forceImpl(const GroupBucket& bucket, const Eigen::VectorXd& x,
                         Eigen::VectorXd& f) const {
  const int k = bucket.k;
  for (int g = 0; g < bucket.groups(); ++g) {
    const NodeMatrix<K> xe = gather<K>(x, bucket.groupNodes(g), k);
    NodeMatrix<K> fe = NodeMatrix<K>::Zero(3, k);
    for (const int e : bucket.members[static_cast<size_t>(g)]) {
      const GradientMap<K> G(gradients_.data() + 3 * slot_[e], k, 3);
      const Eigen::Matrix3d F = xe * G;
      const Eigen::Matrix3d P = options_.rotation == EfgRotation::Polar
                                    ? law_.firstPiola(F)
                                    : rotatedStress(F, matchingRotation(xe, e));
      fe.noalias() -= (grid_.volumes(e) * P) * G.transpose();
    }
    if (options_.stabilization > 0.0) {
      addGroupStabilization<K>(bucket, g, xe, rest_positions_, &fe, nullptr);
    }
    scatter<K>(fe, bucket.groupNodes(g), f);
  }
}

template <int K, typename Sink>
void EfgModel::stiffnessImpl(const GroupBucket& bucket, const Eigen::VectorXd& x, TangentMode mode,
                             Eigen::VectorXd* f, double* energy, Sink&& sink) const {
  // Rotated linear tangents (shape matching, projected polar) accumulate L (see
  // rotatedLinearStiffness) over the group; the exact polar tangent accumulates Ke directly.
  const bool rotated_linear =
      options_.rotation == EfgRotation::ShapeMatching || mode == TangentMode::ProjectedSpd;
  const int k = bucket.k;
  ElementMatrix<K> Ke(3 * k, 3 * k);
  ElementMatrix<K> L(3 * k, 3 * k);
  NodeMatrix<K> fe(3, k);
  NodeMatrix<K> H(3, k);
  for (int g = 0; g < bucket.groups(); ++g) {
    const NodeMatrix<K> xe = gather<K>(x, bucket.groupNodes(g), k);
    (rotated_linear ? L : Ke).setZero();
    fe.setZero();
    for (const int e : bucket.members[static_cast<size_t>(g)]) {
      const GradientMap<K> G(gradients_.data() + 3 * slot_[e], k, 3);
      const double w = grid_.volumes(e);
      const Eigen::Matrix3d F = xe * G;
      Eigen::Matrix3d P;
      if (rotated_linear) {
        Eigen::Matrix3d R;
        if (options_.rotation == EfgRotation::ShapeMatching) {
          R = matchingRotation(xe, e);
          P = rotatedStress(F, R);
          if (energy != nullptr) *energy += w * matchingEnergyDensity(F, R);
        } else {
          const RotatedLinearStressAndTangent point = *law_.rotatedLinearStressAndTangent(F);
          R = point.R;
          P = point.P;
          if (energy != nullptr) *energy += w * point.energy_density;
        }
        H.noalias() = R * G.transpose();
        const Eigen::Map<const RankVector<K>> h(H.data(), 3 * k);
        L.noalias() += (w * h) * h.transpose();
      } else {
        const StressAndTangent point = law_.stressAndTangent(F, mode);
        P = point.P;
        addPointStiffness(point.dPdF, G, w, Ke);
        if (energy != nullptr) *energy += w * law_.energyDensity(F);
      }
      if (f != nullptr) fe.noalias() -= (w * P) * G.transpose();
    }
    if (rotated_linear) rotatedLinearStiffness<K>(L, mu_, lambda_, Ke);
    if (options_.stabilization > 0.0) {
      // The quadratic stabilisation energy 1/2 sum_ab S_ab u_a . u_b: constant stiffness S x I.
      const auto S = groupStabilization<K>(bucket.stabilization, g, k);
      for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b)
          Ke.template block<3, 3>(3 * a, 3 * b).diagonal().array() += S(a, b);
      if (f != nullptr || energy != nullptr) {
        addGroupStabilization<K>(bucket, g, xe, rest_positions_, f != nullptr ? &fe : nullptr,
                                 energy);
      }
    }
    if (f != nullptr) scatter<K>(fe, bucket.groupNodes(g), *f);
    sink(g, Ke);
  }
}

double EfgModel::energy(const Eigen::VectorXd& x) const {
  double energy = 0.0;
  forEachBucket([&](const GroupBucket& bucket, auto size) {
    energy += energyImpl<decltype(size)::value>(bucket, x);
  });
  return energy;
}

void EfgModel::addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  forEachBucket([&](const GroupBucket& bucket, auto size) {
    forceImpl<decltype(size)::value>(bucket, x, f);
  });
}

void EfgModel::addGroupStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                                 double* values) const {
  addGroupStiffnessAndEnergy(x, mode, f, values, nullptr);
}

void EfgModel::addGroupStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode,
                                          Eigen::VectorXd* f, double* values,
                                          double* energy) const {
  if (energy != nullptr) *energy = 0.0;
  forEachBucket([&](const GroupBucket& bucket, auto size) {
    constexpr int K = decltype(size)::value;
    stiffnessImpl<K>(bucket, x, mode, f, energy,
                     [&](int g, const auto& Ke) { bucket.scatter.add(g, Ke, values); });
  });
}

double EfgModel::addInternalForceStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode,
                                                    Eigen::VectorXd& f,
                                                    Eigen::SparseMatrix<double>& K) const {
  double energy = 0.0;
  addGroupStiffnessAndEnergy(x, mode, &f, zeroedValues(K), &energy);
  return energy;
}

void EfgModel::applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                              Eigen::VectorXd& y) const {
  y.setZero(rest_positions_.size());
  forEachBucket([&](const GroupBucket& bucket, auto size) {
    constexpr int K = decltype(size)::value;
    const int k = bucket.k;
    stiffnessImpl<K>(bucket, x, mode, nullptr, nullptr, [&](int g, const auto& Ke) {
      const NodeMatrix<K> ve = gather<K>(v, bucket.groupNodes(g), k);
      const Eigen::Map<const RankVector<K>> vv(ve.data(), 3 * k);
      const RankVector<K> ye = Ke * vv;
      for (int a = 0; a < k; ++a)
        y.segment<3>(3 * bucket.groupNodes(g)[a]) += ye.template segment<3>(3 * a);
    });
  });
}

}  // namespace surgical_sim::core
