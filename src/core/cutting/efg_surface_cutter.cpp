#include "surgical_sim/core/cutting/efg_surface_cutter.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "efg_sweep_slab.h"
#include "index_at.h"
#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/cutting/cut_front.h"
#include "surgical_sim/core/cutting/edge_sweep_ccd.h"
#include "surgical_sim/core/mesh/surface_closure.h"

namespace surgical_sim::core {

using cutting_index::at;
using cutting_index::intSize;

namespace {

/// Edges per broad-phase cluster.
constexpr int kClusterEdges = 32;
/// Consecutive clusters (Morton order) per group of the broad phase's first level.
constexpr int kGroupClusters = 32;
/// The bounds' reference configuration moves to the step's end once a particle is this many
/// mean particle spacings from it [-].
constexpr double kRefitSpacings = 0.5;
/// Crossing parameters are kept this far from the edge ends, and tip barycentric coordinates
/// at least this large, so no split triangle degenerates to zero area.
constexpr double kEdgeMargin = 0.02;
/// Shortest edge a cut splits: this many front widths w, or half the input surface's shortest
/// edge if less [-].
constexpr double kMinSplitEdge = 0.1;
constexpr double kTipMargin = 0.01;

/// Inserts x into the ascending vector v (absent before).
void insertSorted(std::vector<int>& v, int x) {
  v.insert(std::upper_bound(v.begin(), v.end(), x), x);
}

/// Erases x from the ascending vector v (present before).
void eraseSorted(std::vector<int>& v, int x) { v.erase(std::lower_bound(v.begin(), v.end(), x)); }

/// Spreads the 10 low bits of x to every third bit (Morton code).
std::uint32_t spreadBits(std::uint32_t x) {
  x &= 0x3ffu;
  x = (x | (x << 16)) & 0x030000ffu;
  x = (x | (x << 8)) & 0x0300f00fu;
  x = (x | (x << 4)) & 0x030c30c3u;
  x = (x | (x << 2)) & 0x09249249u;
  return x;
}

/// Barycentric coordinates of the crossing of segment [p, q] with triangle (a, b, c), if any.
bool segmentTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                     const Eigen::Vector3d& b, const Eigen::Vector3d& c, Eigen::Vector3d& bary) {
  const Eigen::Vector3d d = q - p, e1 = b - a, e2 = c - a;
  const Eigen::Vector3d h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) <= 1e-14 * d.norm() * e1.norm() * e2.norm()) return false;
  const Eigen::Vector3d s = p - a;
  const double u = s.dot(h) / det;
  const Eigen::Vector3d sq = s.cross(e1);
  const double v = d.dot(sq) / det;
  const double t = e2.dot(sq) / det;
  if (u < 0.0 || v < 0.0 || u + v > 1.0 || t < 0.0 || t > 1.0) return false;
  bary = {1.0 - u - v, u, v};
  return true;
}

Eigen::Vector3d clampBary(Eigen::Vector3d b) {
  b = b.cwiseMax(kTipMargin);
  return b / b.sum();
}

using Positions = EfgSurfaceCutter::Positions;

void checkShape(const char* name, const Positions& x, int n) {
  if (x.cols() != n)
    throw std::invalid_argument(std::string("EfgSurfaceCutter::cut: ") + name + " has " +
                                std::to_string(x.cols()) + " columns, numVertices() is " +
                                std::to_string(n));
}

}  // namespace

EfgSurfaceCutter::EfgSurfaceCutter(const TriMesh& surface, const EfgMappingSource& source,
                                   const EfgSurfaceCutOptions& options)
    : source_(source), options_(options), remapper_(source) {
  if (!(std::isfinite(options.front_width) && options.front_width > 0.0))
    throw std::invalid_argument("EfgSurfaceCutOptions.front_width = " +
                                std::to_string(options.front_width) + " m, must be finite and > 0");
  if (!(std::isfinite(options.tolerance) && options.tolerance >= 0.0))
    throw std::invalid_argument("EfgSurfaceCutOptions.tolerance = " +
                                std::to_string(options.tolerance) + " m, must be finite and >= 0");
  const Eigen::Index n = surface.vertices.cols();
  if (n == 0 || surface.triangles.cols() == 0)
    throw std::invalid_argument("EfgSurfaceCutter: surface has no vertices or no triangles");
  if (!surface.vertices.allFinite())
    throw std::invalid_argument("EfgSurfaceCutter: surface.vertices has a non-finite coordinate");
  for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t) {
    const Eigen::Vector3i tri = surface.triangles.col(t);
    if (tri.minCoeff() < 0 || tri.maxCoeff() >= n)
      throw std::invalid_argument("EfgSurfaceCutter: surface.triangles column " +
                                  std::to_string(t) + " has a vertex outside [0, " +
                                  std::to_string(n) + ")");
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0])
      throw std::invalid_argument("EfgSurfaceCutter: surface.triangles column " +
                                  std::to_string(t) + " repeats a vertex");
  }
  const SurfaceClosure closure = checkSurfaceClosure(surface.triangles);
  if (closure.open_edges != 0 || closure.pinched_edges != 0)
    throw std::invalid_argument("EfgSurfaceCutter: surface must be closed and edge-manifold, has " +
                                std::to_string(closure.open_edges) + " open and " +
                                std::to_string(closure.pinched_edges) + " pinched edges");
  verts_.resize(static_cast<std::size_t>(n));
  segment_tested_.assign(verts_.size(), 0);
  for (Eigen::Index v = 0; v < n; ++v)
    verts_[static_cast<std::size_t>(v)].rest = surface.vertices.col(v);
  tris_.resize(static_cast<std::size_t>(surface.triangles.cols()));
  for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t)
    tris_[static_cast<std::size_t>(t)] = {surface.triangles(0, t), surface.triangles(1, t),
                                          surface.triangles(2, t)};
  commit();
  min_split_edge_ = kMinSplitEdge * options.front_width;
  for (const auto& e : edges_)
    if (e[0] >= 0)
      min_split_edge_ =
          std::min(min_split_edge_, 0.5 * (at(verts_, e[1]).rest - at(verts_, e[0]).rest).norm());
  // Initial mapping: nearest IP below the tangent plane (no 1-ring test: no vertex is mapped).
  ip_vertices_.resize(static_cast<std::size_t>(source_.numIntegrationPoints()));
  ip_x_call_.assign(ip_vertices_.size(), 0);
  ip_x_.resize(ip_vertices_.size());
  for (int v = 0; v < numVertices(); ++v) {
    Vertex& vert = at(verts_, v);
    setIp(v, remapper_.find(vert.rest, vertexNormal(v), vert.planes, {}).ip);
    source_.pointWeights(vert.ip, vert.rest, vert.particles, vert.weights);
  }
  forgetBounds();  // every row is new
  // The reference configuration starts at rest; the mean particle spacing sets the refit
  // distance.
  const int particles = source_.numParticles();
  if (particles < 1) throw std::invalid_argument("EfgSurfaceCutter: the source has no particles");
  Eigen::Matrix3Xd rest(3, particles);
  for (int p = 0; p < particles; ++p) rest.col(p) = source_.particleRestPosition(p);
  if (!rest.allFinite())
    throw std::invalid_argument("EfgSurfaceCutter: a particle rest position is not finite");
  const Eigen::Vector3d extent = rest.rowwise().maxCoeff() - rest.rowwise().minCoeff();
  const double largest = std::max(extent.maxCoeff(), 1e-300);
  refit_distance_ = kRefitSpacings * std::cbrt(extent.cwiseMax(1e-9 * largest).prod() / particles);
  ref_x_ = rest.reshaped();
  refreshClusterBounds();
}

bool EfgSurfaceCutter::vertexUsed(int v) const { return at(verts_, v).used; }
int EfgSurfaceCutter::vertexIp(int v) const { return at(verts_, v).ip; }
int EfgSurfaceCutter::twin(int v) const { return at(verts_, v).twin; }
const std::vector<CutPlane>& EfgSurfaceCutter::vertexPlanes(int v) const {
  return at(verts_, v).planes;
}

Eigen::Matrix3Xd EfgSurfaceCutter::restVertices() const {
  Eigen::Matrix3Xd X(3, numVertices());
  for (int v = 0; v < numVertices(); ++v) X.col(v) = at(verts_, v).rest;
  return X;
}

Eigen::Matrix3Xi EfgSurfaceCutter::triangles() const {
  Eigen::Matrix3Xi out(3, numTriangles());
  Eigen::Index k = 0;
  for (std::size_t t = 0; t < tris_.size(); ++t)
    if (!replaced_[t]) out.col(k++) = Eigen::Map<const Eigen::Vector3i>(tris_[t].data());
  for (const auto& t : generated_) out.col(k++) = Eigen::Map<const Eigen::Vector3i>(t.data());
  return out;
}

int EfgSurfaceCutter::numTriangles() const {
  return live_tris_ - intSize(cut_tris_) + intSize(generated_);
}

std::vector<int> EfgSurfaceCutter::transientVertices() const {
  if (!active_) return {};
  std::vector<int> out = front_;
  out.push_back(tip_vertex_[0]);
  out.push_back(tip_vertex_[1]);
  std::sort(out.begin(), out.end());
  return out;
}

void EfgSurfaceCutter::mappingRow(int v, std::vector<int>& particles,
                                  std::vector<double>& weights) const {
  particles = at(verts_, v).particles;
  weights = at(verts_, v).weights;
}

SurfaceMapping EfgSurfaceCutter::mapping(int nodes) const {
  // A row is the source's pointWeights(): its IP's particles, by ascending particle.
  std::vector<int> vertices, start(verts_.size() + 1, 0), columns;
  std::vector<double> weights;
  for (int v = 0; v < numVertices(); ++v) {
    const Vertex& vert = at(verts_, v);
    if (vert.used) {
      vertices.push_back(v);
      columns.insert(columns.end(), vert.particles.begin(), vert.particles.end());
      weights.insert(weights.end(), vert.weights.begin(), vert.weights.end());
    }
    at(start, v + 1) = intSize(columns);
  }
  return SurfaceMapping::fromRows(nodes, std::move(vertices), std::move(start), std::move(columns),
                                  std::move(weights));
}

// ---------------------------------------------------------------------------------------------
// Committed surface tables.

void EfgSurfaceCutter::commit() {
  if (active_) {
    // The replaced triangles' slots are freed and the generated triangles take the smallest
    // free slots (the same ids with either table option); then the edge tables follow.
    std::vector<int> dead = cut_tris_;
    std::sort(dead.begin(), dead.end());
    for (int t : dead) {
      for (int v : at(tris_, t)) {
        eraseSorted(at(vertex_tris_, v), t);
        updateSegmentTested(v);
      }
      if (!options_.rebuild_tables) unlinkEdges(t);
    }
    tri_free_.insert(tri_free_.end(), dead.begin(), dead.end());
    std::sort(tri_free_.begin(), tri_free_.end(), std::greater<>());
    live_tris_ -= intSize(dead);
    vertex_tris_.resize(verts_.size());
    std::vector<int> added;
    for (const auto& g : generated_) {
      int t = intSize(tris_);
      if (tri_free_.empty()) {
        tris_.push_back(g);
        replaced_.push_back(0);
        tri_edges_.push_back({-1, -1, -1});
      } else {
        t = tri_free_.back();
        tri_free_.pop_back();
        at(tris_, t) = g;
        at(replaced_, t) = 0;
      }
      ++live_tris_;
      for (int v : g) {
        insertSorted(at(vertex_tris_, v), t);
        updateSegmentTested(v);
      }
      added.push_back(t);
    }
    if (options_.rebuild_tables) {
      buildTables();
    } else {
      std::vector<int> fresh;
      for (int t : added) linkEdges(t, fresh);
      addClusters(fresh);
    }
  } else {
    replaced_.assign(tris_.size(), 0);
    live_tris_ = intSize(tris_);
    vertex_tris_.assign(verts_.size(), {});
    for (std::size_t t = 0; t < tris_.size(); ++t)
      for (int v : tris_[t]) at(vertex_tris_, v).push_back(static_cast<int>(t));
    buildTables();
  }
  active_ = false;
  completed_ = false;
  generated_of_.clear();
  crossings_.clear();
  path_.clear();
  row_.clear();
  row_attach_ = {-1, -1};
  front_.clear();
  fixed_sheet_.clear();
  generated_.clear();
  cut_tris_.clear();
  tip_tri_ = {-1, -1};
  tip_vertex_ = {-1, -1};
}

void EfgSurfaceCutter::buildTables() {
  // Edges: (lower, higher, triangle, local edge), sorted.
  std::vector<std::array<int, 4>> uses;
  uses.reserve(3 * static_cast<std::size_t>(live_tris_));
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    if (replaced_[t]) continue;  // a free slot
    for (int k = 0; k < 3; ++k) {
      const int a = tris_[t][static_cast<std::size_t>(k)];
      const int b = tris_[t][static_cast<std::size_t>((k + 1) % 3)];
      uses.push_back({std::min(a, b), std::max(a, b), static_cast<int>(t), k});
    }
  }
  std::sort(uses.begin(), uses.end());
  edges_.clear();
  edge_tris_.clear();
  edge_free_.clear();
  tri_edges_.assign(tris_.size(), {-1, -1, -1});
  for (std::size_t i = 0; i < uses.size(); ++i) {
    if (i == 0 || uses[i][0] != uses[i - 1][0] || uses[i][1] != uses[i - 1][1]) {
      edges_.push_back({uses[i][0], uses[i][1]});
      edge_tris_.push_back({uses[i][2], -1});
    } else {
      edge_tris_.back()[1] = uses[i][2];
    }
    at(tri_edges_, uses[i][2])[static_cast<std::size_t>(uses[i][3])] = intSize(edges_) - 1;
  }
  edge_crossing_.assign(edges_.size(), -1);
  // Clusters: every edge in Morton order of its midpoint in the edges' rest box.
  cluster_box_ = edgeBox();
  std::vector<int> all(edges_.size());
  for (std::size_t e = 0; e < edges_.size(); ++e) all[e] = static_cast<int>(e);
  cluster_edges_.clear();
  cluster_vert_begin_ = {0};
  cluster_vert_ids_.clear();
  edge_cluster_.assign(edges_.size(), -1);
  vertex_clusters_.assign(verts_.size(), {});
  forgetBounds();
  touched_.clear();
  addClusters(all);
}

void EfgSurfaceCutter::unlinkEdges(int t) {
  for (int& e : at(tri_edges_, t)) {
    auto& et = at(edge_tris_, e);
    if (et[0] == t) {
      et[0] = et[1];
      et[1] = -1;
    } else if (et[1] == t) {
      et[1] = -1;
    }
    if (et[0] < 0) {  // no triangle left: free the slot
      std::vector<int>& cluster = at(cluster_edges_, at(edge_cluster_, e));
      *std::find(cluster.begin(), cluster.end(), e) = cluster.back();
      cluster.pop_back();
      at(edge_cluster_, e) = -1;
      at(edges_, e) = {-1, -1};
      at(edge_crossing_, e) = -1;
      edge_free_.push_back(e);
    }
    e = -1;
  }
}

void EfgSurfaceCutter::linkEdges(int t, std::vector<int>& fresh) {
  const auto& tri = at(tris_, t);
  for (std::size_t k = 0; k < 3; ++k) {
    const std::array<int, 2> key = {std::min(tri[k], tri[(k + 1) % 3]),
                                    std::max(tri[k], tri[(k + 1) % 3])};
    // The edge of a linked triangle at the end with fewer triangles, if any.
    const int end = at(vertex_tris_, key[0]).size() <= at(vertex_tris_, key[1]).size() ? 0 : 1;
    int e = -1;
    for (int other : at(vertex_tris_, key[static_cast<std::size_t>(end)])) {
      if (other == t) continue;
      for (int f : at(tri_edges_, other))
        if (f >= 0 && at(edges_, f) == key) e = f;
      if (e >= 0) break;
    }
    if (e < 0) {
      if (edge_free_.empty()) {
        e = intSize(edges_);
        edges_.push_back(key);
        edge_tris_.push_back({t, -1});
        edge_crossing_.push_back(-1);
        edge_cluster_.push_back(-1);
      } else {
        e = edge_free_.back();
        edge_free_.pop_back();
        at(edges_, e) = key;
        at(edge_tris_, e) = {t, -1};
      }
      fresh.push_back(e);
    } else {
      auto& et = at(edge_tris_, e);  // the lower triangle id first, as buildTables
      et[1] = std::max(et[0], t);
      et[0] = std::min(et[0], t);
    }
    at(tri_edges_, t)[k] = e;
  }
}

std::array<Eigen::Vector3d, 2> EfgSurfaceCutter::edgeBox() const {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (const auto& e : edges_)
    for (int v : e) {
      lo = lo.cwiseMin(at(verts_, v).rest);
      hi = hi.cwiseMax(at(verts_, v).rest);
    }
  return {lo, hi};
}

std::uint32_t EfgSurfaceCutter::mortonCode(int e) const {
  const Eigen::Vector3d& lo = cluster_box_[0];
  const Eigen::Vector3d scale = 1023.0 / (cluster_box_[1] - lo).cwiseMax(1e-300).array();
  const Eigen::Vector3d mid =
      0.5 * (at(verts_, at(edges_, e)[0]).rest + at(verts_, at(edges_, e)[1]).rest);
  const Eigen::Vector3d q =
      (mid - lo).cwiseProduct(scale).cwiseMax(0.0).cwiseMin(1023.0);  // a cut stays inside
  return spreadBits(static_cast<std::uint32_t>(q.x())) |
         (spreadBits(static_cast<std::uint32_t>(q.y())) << 1) |
         (spreadBits(static_cast<std::uint32_t>(q.z())) << 2);
}

void EfgSurfaceCutter::addClusters(const std::vector<int>& edges) {
  std::vector<std::pair<std::uint32_t, int>> order;
  order.reserve(edges.size());
  for (int e : edges) order.emplace_back(mortonCode(e), e);
  std::sort(order.begin(), order.end());
  for (std::size_t i = 0; i < order.size(); i += kClusterEdges) {
    std::vector<int>& members = cluster_edges_.emplace_back();
    const auto first = static_cast<long>(cluster_vert_ids_.size());
    for (std::size_t j = i; j < std::min(order.size(), i + kClusterEdges); ++j) {
      const int e = order[j].second;
      members.push_back(e);
      at(edge_cluster_, e) = intSize(cluster_edges_) - 1;
      cluster_vert_ids_.push_back(at(edges_, e)[0]);
      cluster_vert_ids_.push_back(at(edges_, e)[1]);
    }
    std::sort(cluster_vert_ids_.begin() + first, cluster_vert_ids_.end());
    cluster_vert_ids_.erase(std::unique(cluster_vert_ids_.begin() + first, cluster_vert_ids_.end()),
                            cluster_vert_ids_.end());
    cluster_vert_begin_.push_back(intSize(cluster_vert_ids_));
    vertex_clusters_.resize(verts_.size());
    for (auto k = static_cast<std::size_t>(first); k < cluster_vert_ids_.size(); ++k)
      at(vertex_clusters_, cluster_vert_ids_[k]).push_back(intSize(cluster_edges_) - 1);
  }
}

void EfgSurfaceCutter::touch(int v) {
  touched_.push_back(v);
  if (touched_.size() > verts_.size()) {  // cheaper to recompute every bound
    forgetBounds();
    touched_.clear();
  }
}

void EfgSurfaceCutter::forgetBounds() {
  cluster_bounds_.clear();
  group_bounds_.clear();
  super_bounds_.clear();
}

EfgSurfaceCutter::ClusterBound EfgSurfaceCutter::emptyBound() {
  ClusterBound b;
  b.lo.setConstant(std::numeric_limits<double>::infinity());
  b.hi = -b.lo;
  b.segment_lo = b.lo;
  b.segment_hi = b.hi;
  return b;
}

void EfgSurfaceCutter::clusterBox(int c, ClusterBound& b) const {
  const ClusterBound empty = emptyBound();
  b.lo = empty.lo;
  b.hi = empty.hi;
  b.segment_lo = empty.segment_lo;
  b.segment_hi = empty.segment_hi;
  double scale = 0.0;  // largest coordinate [m]
  for (int k = at(cluster_vert_begin_, c); k < at(cluster_vert_begin_, c + 1); ++k) {
    const Vertex& vert = at(verts_, at(cluster_vert_ids_, k));
    if (!vert.used) continue;
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (std::size_t a = 0; a < vert.particles.size(); ++a)
      x += vert.weights[a] * ref_x_.segment<3>(3 * static_cast<Eigen::Index>(vert.particles[a]));
    b.lo = b.lo.cwiseMin(x);
    b.hi = b.hi.cwiseMax(x);
    b.segment_lo = b.segment_lo.cwiseMin(x);
    b.segment_hi = b.segment_hi.cwiseMax(x);
    scale = std::max(scale, x.cwiseAbs().maxCoeff());
    if (vert.ip < 0) continue;
    const Eigen::Vector3d x_ip = source_.ipPositionAt(vert.ip, ref_x_);
    b.segment_lo = b.segment_lo.cwiseMin(x_ip);
    b.segment_hi = b.segment_hi.cwiseMax(x_ip);
    scale = std::max(scale, x_ip.cwiseAbs().maxCoeff());
  }
  // Round-off of the positions the caller maps: far below 1e-9 of the coordinates.
  b.margin = 1e-9 * scale;
}

void EfgSurfaceCutter::unite(ClusterBound& into, const ClusterBound& b) {
  into.lo = into.lo.cwiseMin(b.lo);
  into.hi = into.hi.cwiseMax(b.hi);
  into.segment_lo = into.segment_lo.cwiseMin(b.segment_lo);
  into.segment_hi = into.segment_hi.cwiseMax(b.segment_hi);
  into.row_norm = std::max(into.row_norm, b.row_norm);
  into.margin = std::max(into.margin, b.margin);
}

void EfgSurfaceCutter::refreshClusterBounds() {
  std::vector<int> stale;
  for (int v : touched_)
    if (v < intSize(vertex_clusters_))
      for (int c : at(vertex_clusters_, v))
        if (c < intSize(cluster_bounds_)) stale.push_back(c);
  touched_.clear();
  for (int c = intSize(cluster_bounds_); c < intSize(cluster_edges_); ++c) stale.push_back(c);
  cluster_bounds_.resize(cluster_edges_.size());
  std::sort(stale.begin(), stale.end());
  stale.erase(std::unique(stale.begin(), stale.end()), stale.end());
  const auto groups = [](std::size_t members) {
    return (members + kGroupClusters - 1) / kGroupClusters;
  };
  group_bounds_.resize(groups(cluster_bounds_.size()), emptyBound());
  super_bounds_.resize(groups(group_bounds_.size()), emptyBound());
  for (int c : stale) {
    ClusterBound b;
    clusterBox(c, b);
    for (int k = at(cluster_vert_begin_, c); k < at(cluster_vert_begin_, c + 1); ++k) {
      const Vertex& vert = at(verts_, at(cluster_vert_ids_, k));
      if (!vert.used) continue;
      double norm = 0.0;
      for (const double w : vert.weights) norm += std::abs(w);
      b.row_norm = std::max(b.row_norm, norm);
      if (vert.ip >= 0) b.row_norm = std::max(b.row_norm, source_.ipWeightNorm(vert.ip));
    }
    // Its group and super-group grow to hold it (exact again after the next refit).
    unite(at(group_bounds_, c / kGroupClusters), b);
    unite(at(super_bounds_, c / (kGroupClusters * kGroupClusters)), b);
    at(cluster_bounds_, c) = std::move(b);
  }
}

void EfgSurfaceCutter::refit(const Eigen::VectorXd& x) {
  ref_x_ = x;
  for (int c = 0; c < intSize(cluster_bounds_); ++c) clusterBox(c, at(cluster_bounds_, c));
  uniteGroups(cluster_bounds_, group_bounds_);
  uniteGroups(group_bounds_, super_bounds_);
}

void EfgSurfaceCutter::uniteGroups(const std::vector<ClusterBound>& members,
                                   std::vector<ClusterBound>& groups) {
  for (int g = 0; g < intSize(groups); ++g) {
    ClusterBound& group = at(groups, g) = emptyBound();
    const int end = std::min(intSize(members), (g + 1) * kGroupClusters);
    for (int m = g * kGroupClusters; m < end; ++m) unite(group, at(members, m));
  }
}

void EfgSurfaceCutter::measureMotion(const EfgParticleMotion& motion) {
  const Eigen::Index size = ref_x_.size();
  if (motion.start.size() != size || motion.end.size() != size)
    throw std::invalid_argument("EfgSurfaceCutter::cut: particle positions have sizes " +
                                std::to_string(motion.start.size()) + " and " +
                                std::to_string(motion.end.size()) + ", expected " +
                                std::to_string(size));
  for (int ip : motion.changed_ips) {
    if (ip < 0 || ip >= intSize(ip_vertices_))
      throw std::invalid_argument("EfgSurfaceCutter::cut: changed IP " + std::to_string(ip) +
                                  " outside [0, " + std::to_string(ip_vertices_.size()) + ")");
  }
  for (int ip : motion.changed_ips)
    for (int v : at(ip_vertices_, ip)) touch(v);
  for (bool refitted = false;; refitted = true) {
    double moved = 0.0;      // squared [m^2]
    double round_off = 0.0;  // x - x sums to 0, or NaN after a non-finite coordinate
    for (Eigen::Index p = 0; 3 * p < size; ++p) {
      const double a = (motion.start.segment<3>(3 * p) - ref_x_.segment<3>(3 * p)).squaredNorm();
      const double b = (motion.end.segment<3>(3 * p) - ref_x_.segment<3>(3 * p)).squaredNorm();
      round_off += (a - a) + (b - b);
      moved = std::max({moved, a, b});
    }
    if (round_off != 0.0)
      throw std::invalid_argument(
          "EfgSurfaceCutter::cut: a particle position at the step start or end is not finite");
    motion_ = std::sqrt(moved);
    // Far from the reference, the bounds are loose: the step end becomes the reference.
    if (refitted || motion_ <= refit_distance_) return;
    refit(motion.end);
  }
}

int EfgSurfaceCutter::newVertex(Eigen::Vector3d rest) {  // by value: verts_ may reallocate
  int v;
  if (!free_.empty()) {
    v = free_.back();
    free_.pop_back();
  } else {
    v = numVertices();
    verts_.emplace_back();
    segment_tested_.push_back(0);
  }
  Vertex& vert = at(verts_, v);
  vert = Vertex{};
  vert.rest = rest;
  touch(v);
  return v;
}

void EfgSurfaceCutter::setIp(int v, int ip) {
  Vertex& vert = at(verts_, v);
  if (vert.ip >= 0) {  // v's slot takes the list's last vertex
    std::vector<int>& old = at(ip_vertices_, vert.ip);
    const int last = old.back();
    at(old, vert.ip_slot) = last;
    at(verts_, last).ip_slot = vert.ip_slot;
    old.pop_back();
  }
  vert.ip = ip;
  vert.ip_slot = -1;
  if (ip >= 0) {
    std::vector<int>& list = at(ip_vertices_, ip);
    vert.ip_slot = intSize(list);
    list.push_back(v);
  }
  updateSegmentTested(v);
}

void EfgSurfaceCutter::updateSegmentTested(int v) {
  const bool committed = v < intSize(vertex_tris_) && !at(vertex_tris_, v).empty();
  at(segment_tested_, v) = at(verts_, v).ip >= 0 && committed ? 1 : 0;
}

void EfgSurfaceCutter::freeVertex(int v) {
  setIp(v, -1);
  at(verts_, v) = Vertex{};
  at(verts_, v).used = false;
  free_.push_back(v);
  touch(v);
}

// ---------------------------------------------------------------------------------------------
// Crossings and tips.

int EfgSurfaceCutter::crossingCopy(int c, int vertex) const {
  const Crossing& x = at(crossings_, c);
  return x.copy[at(edges_, x.edge)[0] == vertex ? 0 : 1];
}

int EfgSurfaceCutter::crossedCount(int tri) const {
  int n = 0;
  for (int e : at(tri_edges_, tri)) n += at(edge_crossing_, e) >= 0 ? 1 : 0;
  return n;
}

bool EfgSurfaceCutter::accept(int edge, double s) {
  s = std::clamp(s, kEdgeMargin, 1.0 - kEdgeMargin);
  const auto& ev = at(edges_, edge);
  auto addCrossing = [&](int a_end) {
    Crossing c;
    c.edge = edge;
    c.s = s;
    c.a_end = a_end;
    const Eigen::Vector3d X = (1.0 - s) * at(verts_, ev[0]).rest + s * at(verts_, ev[1]).rest;
    c.copy[0] = newVertex(X);
    c.copy[1] = newVertex(X);
    at(verts_, c.copy[0]).twin = c.copy[1];
    at(verts_, c.copy[1]).twin = c.copy[0];
    crossings_.push_back(c);
    at(edge_crossing_, edge) = intSize(crossings_) - 1;
    return intSize(crossings_) - 1;
  };
  auto enterTriangle = [&](int end, int tri) {
    tip_tri_[static_cast<std::size_t>(end)] = tri;
    if (!at(replaced_, tri)) {
      at(replaced_, tri) = 1;
      cut_tris_.push_back(tri);
    }
    // Default tip: a third of the way from the crossing to the opposite corner.
    const auto& te = at(tri_edges_, tri);
    const int k = static_cast<int>(std::find(te.begin(), te.end(), edge) - te.begin());
    const int a = at(tris_, tri)[static_cast<std::size_t>(k)];
    const double s_a = ev[0] == a ? s : 1.0 - s;
    Eigen::Vector3d b;
    b[k] = 2.0 / 3.0 * (1.0 - s_a);
    b[(k + 1) % 3] = 2.0 / 3.0 * s_a;
    b[(k + 2) % 3] = 1.0 / 3.0;
    tip_bary_[static_cast<std::size_t>(end)] = clampBary(b);
  };
  if (at(edge_crossing_, edge) >= 0) return false;
  if ((at(verts_, ev[1]).rest - at(verts_, ev[0]).rest).norm() < min_split_edge_) return false;
  if (!active_) {
    active_ = true;
    path_ = {addCrossing(0)};
    for (int end = 0; end < 2; ++end) {
      enterTriangle(end, at(edge_tris_, edge)[static_cast<std::size_t>(end)]);
      tip_vertex_[static_cast<std::size_t>(end)] = newVertex(Eigen::Vector3d::Zero());
    }
    return true;
  }
  if (completed_) return false;
  for (int end = 0; end < 2; ++end) {
    const int tri = tip_tri_[static_cast<std::size_t>(end)];
    const auto& te = at(tri_edges_, tri);
    if (std::find(te.begin(), te.end(), edge) == te.end()) continue;
    const auto& et = at(edge_tris_, edge);
    const int other = et[0] == tri ? et[1] : et[0];
    const bool closing = other == tip_tri_[static_cast<std::size_t>(1 - end)];
    if (!closing && crossedCount(other) != 0) return false;
    // The corner shared with the end crossing's edge keeps its side.
    const Crossing& last = at(crossings_, end == 0 ? path_.front() : path_.back());
    const auto& lv = at(edges_, last.edge);
    const int v = (lv[0] == ev[0] || lv[1] == ev[0]) ? ev[0] : ev[1];
    const bool v_on_a = lv[static_cast<std::size_t>(last.a_end)] == v;
    const int c = addCrossing((ev[0] == v) == v_on_a ? 0 : 1);
    if (end == 0)
      path_.insert(path_.begin(), c);
    else
      path_.push_back(c);
    if (closing) {
      tip_tri_[static_cast<std::size_t>(end)] = other;
      completed_ = true;
    } else {
      enterTriangle(end, other);
    }
    return true;
  }
  return false;
}

bool EfgSurfaceCutter::placeTip(int end, const BladeSweep& sweep, const Positions& x_end) {
  const auto& tri = at(tris_, tip_tri_[static_cast<std::size_t>(end)]);
  Eigen::Vector3d bary;
  bool pierced = false;
  for (Eigen::Index i = 0; i + 1 < sweep.end.cols() && !pierced; ++i)
    pierced = segmentTriangle(sweep.end.col(i), sweep.end.col(i + 1), x_end.col(tri[0]),
                              x_end.col(tri[1]), x_end.col(tri[2]), bary);
  if (pierced) tip_bary_[static_cast<std::size_t>(end)] = clampBary(bary);
  const Eigen::Vector3d& b = tip_bary_[static_cast<std::size_t>(end)];
  at(verts_, tip_vertex_[static_cast<std::size_t>(end)]).rest = b[0] * at(verts_, tri[0]).rest +
                                                                b[1] * at(verts_, tri[1]).rest +
                                                                b[2] * at(verts_, tri[2]).rest;
  return pierced;
}

// ---------------------------------------------------------------------------------------------
// Front and exposed surface.

std::vector<int> EfgSurfaceCutter::chain() const {
  auto copyA = [this](int c) { return at(crossings_, c).copy[at(crossings_, c).a_end]; };
  std::vector<int> out;
  const int n = intSize(path_);
  int i_l = n - 1, i_r = 0;
  if (!row_.empty()) {
    i_l = static_cast<int>(std::find(path_.begin(), path_.end(), row_attach_[0]) - path_.begin());
    i_r = static_cast<int>(std::find(path_.begin(), path_.end(), row_attach_[1]) - path_.begin());
  }
  for (int i = 0; i <= i_l; ++i) out.push_back(copyA(at(path_, i)));
  if (!row_.empty()) {
    out.insert(out.end(), row_.begin(), row_.end());
    for (int i = i_r; i < n; ++i) out.push_back(copyA(at(path_, i)));
  }
  return out;
}

void EfgSurfaceCutter::updateFront(std::vector<int>& created) {
  const Eigen::Vector3d X_l = at(verts_, tip_vertex_[0]).rest;
  const Eigen::Vector3d X_r = at(verts_, tip_vertex_[1]).rest;
  const double w = options_.front_width;
  const int k = frontSegmentCount((X_r - X_l).norm(), intSize(front_) + 1, w);
  while (intSize(front_) > k - 1) {
    freeVertex(front_.back());
    front_.pop_back();
  }
  while (intSize(front_) < k - 1) {
    front_.push_back(newVertex(Eigen::Vector3d::Zero()));
    created.push_back(front_.back());
  }
  for (int i = 0; i < k - 1; ++i)
    at(verts_, at(front_, i)).rest = X_l + (X_r - X_l) * (i + 1.0) / k;
  // Drop a row of fixed vertices once the front is farther than w from the chain behind it.
  const std::vector<int> behind = chain();
  double farthest = 0.0;
  for (int t : front_) {
    double nearest = std::numeric_limits<double>::max();
    for (int b : behind)
      nearest = std::min(nearest, (at(verts_, t).rest - at(verts_, b).rest).norm());
    farthest = std::max(farthest, nearest);
  }
  // A row needs distinct chain ends to attach to (a path of one crossing has one).
  if (farthest <= w || path_.size() < 2) return;
  std::vector<int> row;
  for (int t : front_) row.push_back(newPair(at(verts_, t).rest, created));
  std::vector<int> ahead = {behind.front()};
  ahead.insert(ahead.end(), row.begin(), row.end());
  ahead.push_back(behind.back());
  gradedStrip(behind, ahead, created, fixed_sheet_);
  row_ = std::move(row);
  row_attach_ = {path_.front(), path_.back()};
}

int EfgSurfaceCutter::newPair(Eigen::Vector3d rest, std::vector<int>& created) {
  const int a = newVertex(rest), b = newVertex(rest);
  at(verts_, a).twin = b;
  at(verts_, b).twin = a;
  created.push_back(a);
  created.push_back(b);
  return a;
}

void EfgSurfaceCutter::gradedStrip(std::vector<int> behind, std::vector<int> ahead,
                                   std::vector<int>& created,
                                   std::vector<std::array<int, 3>>& out) {
  // The denser chain is halved towards the other; with the roles swapped the strip is built
  // about the opposite normal and its triangles are turned back.
  const bool swapped = gradingLevels(ahead.size(), behind.size()) > 0;
  if (swapped) std::swap(behind, ahead);
  const std::size_t first = out.size();
  const int levels = gradingLevels(behind.size(), ahead.size());
  for (int level = 0; level < levels; ++level) {
    // Rows evenly spaced from the dense chain to the sparse one.
    const double f = 1.0 / (levels - level + 1);
    // Row vertex k stands over behind's vertex 2k (the last over behind's last); the strip
    // between them is made piece by piece, so each row vertex takes at most three behind
    // vertices.
    std::vector<int> row = {behind.front()};
    for (const Eigen::Vector3d& p : halvingRow(behind, ahead, restOf(), f))
      row.push_back(newPair(p, created));
    row.push_back(behind.back());
    for (std::size_t k = 0; k + 1 < row.size(); ++k) {
      const auto from = behind.begin() + static_cast<long>(2 * k);
      const auto to = k + 2 == row.size() ? behind.end() : from + 3;
      appendStrip({from, to}, {row[k], row[k + 1]}, restOf(), out);
    }
    behind = std::move(row);
  }
  appendStrip(behind, ahead, restOf(), out);
  if (swapped)
    for (std::size_t k = first; k < out.size(); ++k) std::swap(out[k][1], out[k][2]);
}

std::function<Eigen::Vector3d(int)> EfgSurfaceCutter::restOf() const {
  return [this](int v) { return at(verts_, v).rest; };
}

void EfgSurfaceCutter::rebuild(bool crack, std::vector<int>& created) {
  generated_.clear();
  for (int t : cut_tris_) {
    const auto& tri = at(tris_, t);
    const auto& te = at(tri_edges_, t);
    std::array<int, 3> c{};
    for (std::size_t k = 0; k < 3; ++k) c[k] = at(edge_crossing_, te[k]);
    const int crossed = (c[0] >= 0) + (c[1] >= 0) + (c[2] >= 0);
    if (crossed == 2) {
      // Corner v between the two crossed edges (v, p) and (r, v).
      std::size_t i = 0;
      while (!(c[i] >= 0 && c[(i + 2) % 3] >= 0)) ++i;
      const int v = tri[i], p = tri[(i + 1) % 3], r = tri[(i + 2) % 3];
      const int c_vp = c[i], c_rv = c[(i + 2) % 3];
      generated_.push_back({v, crossingCopy(c_vp, v), crossingCopy(c_rv, v)});
      generated_.push_back({crossingCopy(c_vp, p), p, r});
      generated_.push_back({crossingCopy(c_vp, p), r, crossingCopy(c_rv, r)});
    } else {
      const std::size_t i = c[0] >= 0 ? 0 : (c[1] >= 0 ? 1 : 2);
      const int a = tri[i], b = tri[(i + 1) % 3], d = tri[(i + 2) % 3];
      const int tip = tip_vertex_[tip_tri_[0] == t ? 0 : 1];
      generated_.push_back({a, crossingCopy(c[i], a), tip});
      generated_.push_back({crossingCopy(c[i], b), b, tip});
      generated_.push_back({b, d, tip});
      generated_.push_back({d, a, tip});
    }
  }
  std::vector<std::array<int, 3>> sheet = fixed_sheet_;
  const std::vector<int> behind = chain();
  if (completed_) {
    // Fill the closed chain: a strip from its last fixed row to the rest of the polygon walked
    // the other way round; without a row, between the polygon's two halves.
    std::vector<int> upper, lower;
    if (row_.empty()) {
      const auto m = static_cast<long>(behind.size() / 2);
      upper.assign(behind.begin(), behind.begin() + m + 1);
      lower = {behind.front()};
      lower.insert(lower.end(), behind.rbegin(), behind.rend() - m);
    } else {
      const auto m = std::find(path_.begin(), path_.end(), row_attach_[0]) - path_.begin();
      const auto end = m + static_cast<long>(row_.size()) + 1;
      upper.assign(behind.begin() + m, behind.begin() + end + 1);
      lower.assign(behind.rend() - m - 1, behind.rend());
      lower.insert(lower.end(), behind.rbegin(), behind.rend() - end);
    }
    gradedStrip(upper, lower, created, sheet);
  } else {
    std::vector<int> ahead = {tip_vertex_[0]};
    ahead.insert(ahead.end(), front_.begin(), front_.end());
    ahead.push_back(tip_vertex_[1]);
    if (crack)
      gradedStrip(behind, ahead, created, sheet);
    else
      appendStrip(behind, ahead, restOf(), sheet);
  }
  // Orientation: the sheet must use each slit edge against the split triangles' direction.
  std::vector<std::pair<int, int>> split_edges;
  for (const auto& t : generated_)
    for (std::size_t k = 0; k < 3; ++k) split_edges.emplace_back(t[k], t[(k + 1) % 3]);
  std::sort(split_edges.begin(), split_edges.end());
  auto used = [&](int a, int b) {
    return std::binary_search(split_edges.begin(), split_edges.end(), std::make_pair(a, b));
  };
  auto mustFlip = [&] {
    for (const auto& t : sheet)
      for (std::size_t k = 0; k < 3; ++k) {
        if (used(t[k], t[(k + 1) % 3])) return true;
        if (used(t[(k + 1) % 3], t[k])) return false;
      }
    return false;
  };
  const bool flip = mustFlip();
  auto other = [this](int v) { return at(verts_, v).twin >= 0 ? at(verts_, v).twin : v; };
  sheet_start_ = intSize(generated_);
  for (const auto& t : sheet) {
    if (flip) {
      generated_.push_back({t[0], t[2], t[1]});
      generated_.push_back({other(t[0]), other(t[1]), other(t[2])});
    } else {
      generated_.push_back(t);
      generated_.push_back({other(t[0]), other(t[2]), other(t[1])});
    }
  }
  generated_of_.clear();
  for (int k = 0; k < intSize(generated_); ++k)
    for (int v : at(generated_, k)) generated_of_.emplace_back(v, k);
  std::sort(generated_of_.begin(), generated_of_.end());
}

std::pair<std::vector<std::pair<int, int>>::const_iterator,
          std::vector<std::pair<int, int>>::const_iterator>
EfgSurfaceCutter::generatedOf(int v) const {
  return std::equal_range(generated_of_.begin(), generated_of_.end(), v, GeneratedOrder{});
}

// ---------------------------------------------------------------------------------------------
// Mapping.

template <class F>
void EfgSurfaceCutter::forIncident(int v, const F& f) const {
  if (v < intSize(vertex_tris_))
    for (int t : at(vertex_tris_, v))
      if (!at(replaced_, t)) f(at(tris_, t));
  const auto [first, last] = generatedOf(v);
  for (auto it = first; it != last; ++it) f(at(generated_, it->second));
}

Eigen::Vector3d EfgSurfaceCutter::sheetNormal(int v) const {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  const auto [first, last] = generatedOf(v);
  for (auto it = first; it != last; ++it) {
    const int k = it->second;
    if (k < sheet_start_ || (k - sheet_start_) % 2 != 0) continue;  // side A sheet only
    const auto& t = at(generated_, k);
    const Eigen::Vector3d &a = at(verts_, t[0]).rest, &b = at(verts_, t[1]).rest,
                          &c = at(verts_, t[2]).rest;
    n += (b - a).cross(c - a);
  }
  const double len = n.norm();
  return len > 1e-300 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

Eigen::Vector3d EfgSurfaceCutter::vertexNormal(int v) const {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  forIncident(v, [&](const std::array<int, 3>& t) {
    const Eigen::Vector3d &a = at(verts_, t[0]).rest, &b = at(verts_, t[1]).rest,
                          &c = at(verts_, t[2]).rest;
    n += (b - a).cross(c - a);
  });
  const double len = n.norm();
  return len > 1e-300 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

void EfgSurfaceCutter::remap(int v, const std::vector<std::uint8_t>* excluded,
                             std::vector<int>* near, bool weights_current) {
  Vertex& vert = at(verts_, v);
  const int ip = vert.ip;
  if (!vert.sliver) {
    std::vector<int> ring;
    forIncident(v, [&](const std::array<int, 3>& t) {
      for (int u : t) {
        const int ring_ip = at(verts_, u).ip;
        if (u != v && ring_ip >= 0 && !(excluded && at(*excluded, ring_ip)))
          ring.push_back(ring_ip);
      }
    });
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    std::vector<int> own;
    std::vector<int>& ips = near ? *near : own;
    if (ips.empty()) ips = remapper_.nearby(vert.rest);
    const RemapResult found = remapper_.find(vert.rest, vertexNormal(v), vert.planes, ring, ips);
    setIp(v, found.ip);
    vert.sliver = found.relaxation == RemapRelaxation::kNearest;
  }
  if (weights_current && vert.ip == ip) return;
  source_.pointWeights(vert.ip, vert.rest, vert.particles, vert.weights);
  touch(v);
}

void EfgSurfaceCutter::addPlane(int v, const Eigen::Vector3d& point,
                                const Eigen::Vector3d& normal) {
  if (normal.squaredNorm() > 0.0) at(verts_, v).planes.push_back({point, normal});
}

std::vector<int> EfgSurfaceCutter::remapVerticesOfIps(const std::vector<int>& changed_ips) {
  const int n = source_.numIntegrationPoints();
  std::vector<std::uint8_t> changed(static_cast<std::size_t>(n), 0);
  for (int ip : changed_ips) {
    if (ip < 0 || ip >= n)
      throw std::invalid_argument("EfgSurfaceCutter::remapVerticesOfIps: IP " + std::to_string(ip) +
                                  " outside [0, " + std::to_string(n) + ")");
    at(changed, ip) = 1;
  }
  std::vector<int> out;
  for (int ip : changed_ips)
    if (at(changed, ip) == 1) {
      at(changed, ip) = 2;  // listed once
      out.insert(out.end(), at(ip_vertices_, ip).begin(), at(ip_vertices_, ip).end());
    }
  std::sort(out.begin(), out.end());
  // The 1-ring test first ignores the changed IPs (their sets are what changed), then a second
  // pass sees every neighbour's new IP (a sliver has no search to repeat; a vertex that keeps its
  // IP keeps the weights the first pass gave it).
  std::vector<std::vector<int>> near(out.size());
  for (std::size_t i = 0; i < out.size(); ++i) remap(out[i], &changed, &near[i]);
  for (std::size_t i = 0; i < out.size(); ++i)
    if (!at(verts_, out[i]).sliver && at(changed, at(verts_, out[i]).ip))
      remap(out[i], nullptr, &near[i], true);
  return out;
}

// ---------------------------------------------------------------------------------------------
// One step.

EfgSurfaceCutStep EfgSurfaceCutter::cut(const BladeSweep& sweep, const Positions& x_start,
                                        const Positions& x_end, const EfgParticleMotion* motion) {
  validateBladeSweep(sweep);
  checkShape("x_start", x_start, numVertices());
  checkShape("x_end", x_end, numVertices());
  EfgSurfaceCutStep out;
  const Stopwatch detect;
  if (motion) {
    measureMotion(*motion);
    refreshClusterBounds();
  }
  const double tol = options_.tolerance;
  const Eigen::AlignedBox3d blade_box = sweepBox(sweep, tol);
  const Eigen::Vector3d blade_lo = blade_box.min(), blade_hi = blade_box.max();
  const Eigen::Index segments = sweep.start.cols() - 1;

  std::vector<efg_sweep_slab::SweepSlab> slabs;
  for (Eigen::Index i = 0; i < segments; ++i)
    slabs.push_back(efg_sweep_slab::sweepSlab(sweep, i, tol));
  // A one-segment blade's slab is a fourth axis: its normal, and its faces as the box's. Without
  // one (zero normal, both faces at 0) every point projects to 0, inside: the axis sets no bit.
  const efg_sweep_slab::SweepSlab slab =
      segments == 1 ? slabs.front() : efg_sweep_slab::SweepSlab{};

  // Outcodes: bit d (d + 4) when the vertex stays below (above) the blade's swept box along axis
  // d over the step, axis 3 the slab's normal (no bit without a slab). classify(v) also checks
  // v's positions, reading only them, without branches (x - x sums to 0, or NaN after a
  // non-finite coordinate).
  outcode_.resize(verts_.size());
  double round_off = 0.0;
  const double box_lo[4] = {blade_lo.x(), blade_lo.y(), blade_lo.z(), slab.lo};
  const double box_hi[4] = {blade_hi.x(), blade_hi.y(), blade_hi.z(), slab.hi};
  const auto classify = [&](int v) {
    const double* a = x_start.col(v).data();
    const double* b = x_end.col(v).data();
    const double pa[4] = {a[0], a[1], a[2],
                          slab.normal.x() * a[0] + slab.normal.y() * a[1] + slab.normal.z() * a[2]};
    const double pb[4] = {b[0], b[1], b[2],
                          slab.normal.x() * b[0] + slab.normal.y() * b[1] + slab.normal.z() * b[2]};
    unsigned code = 0;
    for (int d = 0; d < 4; ++d) {
      round_off += (pa[d] - pa[d]) + (pb[d] - pb[d]);
      const double lo = std::min(pa[d], pb[d]), hi = std::max(pa[d], pb[d]);
      code |= static_cast<unsigned>(hi < box_lo[d]) << d;
      code |= static_cast<unsigned>(lo > box_hi[d]) << (d + 4);
    }
    outcode_[static_cast<std::size_t>(v)] = static_cast<std::uint8_t>(code);
  };
  // The committed surface's mapped vertices whose segment to their IP is tested (`near`, each
  // once), and the clusters to test edge by edge.
  std::vector<int> near, clusters;
  if (!motion) {
    for (int v = 0; v < numVertices(); ++v) {
      classify(v);
      if (at(segment_tested_, v)) near.push_back(v);
    }
    clusters.resize(cluster_edges_.size());
    for (std::size_t c = 0; c < clusters.size(); ++c) clusters[c] = static_cast<int>(c);
  } else {
    // A cluster's vertices (and their IPs) stay within `grow` of their box at the reference:
    // a cluster (group) whose segment box so grown misses the swept box and slab is skipped,
    // one whose vertex box so grown meets them is classified and tested edge by edge.
    const auto meets = [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double grow) {
      return (hi.array() + grow >= blade_lo.array()).all() &&
             (lo.array() - grow <= blade_hi.array()).all() && slab.boxGap(lo, hi) <= grow;
    };
    const auto growth = [&](const ClusterBound& b) {
      return b.row_norm * motion_ * (1.0 + 1e-9) + b.margin;
    };
    vertex_mark_.resize(verts_.size(), 0);
    std::vector<int> marked;
    const auto skipped = [&](const ClusterBound& b) {
      return !meets(b.segment_lo, b.segment_hi, growth(b));
    };
    for (int sg = 0; sg < intSize(super_bounds_); ++sg) {
      if (skipped(at(super_bounds_, sg))) continue;
      const int groups_end = std::min(intSize(group_bounds_), (sg + 1) * kGroupClusters);
      for (int g = sg * kGroupClusters; g < groups_end; ++g) {
        if (skipped(at(group_bounds_, g))) continue;
        const int end = std::min(intSize(cluster_edges_), (g + 1) * kGroupClusters);
        for (int c = g * kGroupClusters; c < end; ++c) {
          if (at(cluster_edges_, c).empty()) continue;  // all its edges freed
          const ClusterBound& b = at(cluster_bounds_, c);
          const double grow = growth(b);
          if (!meets(b.segment_lo, b.segment_hi, grow)) continue;
          // Mark bit 1: listed in `near`; bit 2: classified.
          const bool edges = meets(b.lo, b.hi, grow);
          for (int k = at(cluster_vert_begin_, c); k < at(cluster_vert_begin_, c + 1); ++k) {
            const int v = at(cluster_vert_ids_, k);
            std::uint8_t& mark = at(vertex_mark_, v);
            if (!mark) marked.push_back(v);
            if (!(mark & 1) && at(segment_tested_, v)) {
              mark |= 1;
              near.push_back(v);
            }
            if (edges && !(mark & 2)) {
              mark |= 2;
              classify(v);
            }
          }
          if (edges) clusters.push_back(c);
        }
      }
    }
    for (int v : marked) at(vertex_mark_, v) = 0;
  }
  const bool finite = round_off == 0.0;
  if (!finite)
    throw std::invalid_argument(
        "EfgSurfaceCutter::cut: x_start or x_end has a non-finite coordinate");

  // Broad phase: a cluster whose vertices all stay on one side of the swept box is skipped; the
  // others test every blade segment against their uncut edges.
  struct Hit {
    double t;
    int edge;
    double s;
  };
  std::vector<Hit> hits;
  for (int c : clusters) {
    // Every vertex of the cluster's edges (and maybe a few more) on one side of the box.
    if (at(cluster_edges_, c).empty()) continue;  // all its edges freed
    std::uint8_t common = 0xff;
    for (int k = at(cluster_vert_begin_, c); k < at(cluster_vert_begin_, c + 1); ++k)
      common &= at(outcode_, at(cluster_vert_ids_, k));
    if (common) continue;
    for (int e : at(cluster_edges_, c)) {
      if (at(edge_crossing_, e) >= 0) continue;
      const int a = at(edges_, e)[0], b = at(edges_, e)[1];
      if (at(outcode_, a) & at(outcode_, b)) continue;
      std::optional<EdgeSweepHit> best;
      for (Eigen::Index i = 0; i < segments; ++i) {
        if (at(slabs, static_cast<int>(i))
                .apart({x_start.col(a), x_start.col(b), x_end.col(a), x_end.col(b)}))
          continue;
        const auto hit = edgeSweepCrossing(sweep.start.col(i), sweep.start.col(i + 1),
                                           sweep.end.col(i), sweep.end.col(i + 1), x_start.col(a),
                                           x_start.col(b), x_end.col(a), x_end.col(b), tol);
        if (hit && (!best || hit->t < best->t)) best = hit;
      }
      if (best) hits.push_back({best->t, e, best->s});
    }
  }
  // Blade crossing the segment from a vertex to its IP (IP held at its current position).
  // An IP's position is computed once a call. At every time of the step the segment lies in
  // the hull of the vertex's two positions and the IP's, and a crossing is a point of it within
  // tol of the blade, so inside the swept box: a hull whose box misses the swept box is skipped.
  std::vector<std::pair<int, CutPlane>> ip_hits;
  ++calls_;
  for (int v : near) {
    const int ip = at(verts_, v).ip;
    Eigen::Vector3d& x_ip = at(ip_x_, ip);
    if (at(ip_x_call_, ip) != calls_) {
      at(ip_x_call_, ip) = calls_;
      x_ip = source_.ipPosition(ip);
    }
    const Eigen::Vector3d lo = x_start.col(v).cwiseMin(x_end.col(v)).cwiseMin(x_ip);
    const Eigen::Vector3d hi = x_start.col(v).cwiseMax(x_end.col(v)).cwiseMax(x_ip);
    if ((hi.array() < blade_lo.array()).any() || (lo.array() > blade_hi.array()).any()) continue;
    for (Eigen::Index i = 0; i < segments; ++i) {
      if (at(slabs, static_cast<int>(i)).apart({x_start.col(v), x_end.col(v), x_ip})) continue;
      const auto hit =
          edgeSweepCrossing(sweep.start.col(i), sweep.start.col(i + 1), sweep.end.col(i),
                            sweep.end.col(i + 1), x_start.col(v), x_ip, x_end.col(v), x_ip, tol);
      if (!hit) continue;
      const Vertex& vert = at(verts_, v);
      const Eigen::Vector3d d = source_.ipRestPosition(ip) - vert.rest;
      if (d.squaredNorm() > 0.0) ip_hits.push_back({v, {vert.rest + hit->s * d, d.normalized()}});
      break;
    }
  }
  // In vertex order, as the pass over every vertex lists them.
  std::sort(ip_hits.begin(), ip_hits.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  out.detect_seconds = detect.seconds();
  if (hits.empty() && ip_hits.empty() && !active_) return out;

  // Accept crossings in time order; one pass may enable others (a tip moved next to them).
  // Ties in time by the edge's vertices (edge ids depend on the table option).
  std::sort(hits.begin(), hits.end(), [this](const Hit& x, const Hit& y) {
    return x.t < y.t || (x.t == y.t && at(edges_, x.edge) < at(edges_, y.edge));
  });
  const int first_crossing = intSize(crossings_);
  // Passes over the hits in that order, accepting what accept() takes, until a pass takes none.
  // A running cut takes only edges of its tip triangles, so each pass visits just the hits on
  // those (accept() has no effect when it declines).
  std::vector<std::pair<int, int>> hit_of_edge;  // (edge, hit), sorted
  for (int i = 0; i < intSize(hits); ++i) hit_of_edge.emplace_back(at(hits, i).edge, i);
  std::sort(hit_of_edge.begin(), hit_of_edge.end());
  std::vector<std::uint8_t> taken(hits.size(), 0);
  const auto take = [&](int i) {
    at(taken, i) = 1;
    ++out.crossed_edges;
  };
  for (int i = 0; !active_ && i < intSize(hits); ++i)
    if (accept(at(hits, i).edge, at(hits, i).s)) take(i);
  for (bool progress = active_; progress;) {
    progress = false;
    for (int next = 0;;) {
      // The first hit from `next` on that accept() takes, among those on the tip triangles.
      std::vector<int> candidates;
      if (!completed_)
        for (int tri : tip_tri_)
          for (int e : at(tri_edges_, tri)) {
            const auto it = std::lower_bound(hit_of_edge.begin(), hit_of_edge.end(),
                                             std::pair<int, int>{e, -1});
            if (it != hit_of_edge.end() && it->first == e && it->second >= next &&
                !at(taken, it->second))
              candidates.push_back(it->second);
          }
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      int accepted = -1;
      for (int i : candidates)
        if (accept(at(hits, i).edge, at(hits, i).s)) {
          accepted = i;
          break;
        }
      if (accepted < 0) break;
      take(accepted);
      progress = true;
      next = accepted + 1;
    }
  }
  out.ignored_crossings = intSize(hits) - out.crossed_edges;
  std::vector<int> to_remap;
  for (const auto& h : ip_hits) {
    addPlane(h.first, h.second.point, h.second.normal);
    to_remap.push_back(h.first);
  }
  if (active_) {
    bool pierced = false;
    if (!completed_) {
      const bool left = placeTip(0, sweep, x_end), right = placeTip(1, sweep, x_end);
      pierced = left || right;
    }
    // New fixed vertices (rows, graded strips) and transient ones.
    std::vector<int> created;
    if (!completed_) updateFront(created);
    rebuild(!completed_ && !pierced, created);
    // Planes with the cut's normal: each endpoint and copy of a new crossing, through it.
    for (int c = first_crossing; c < intSize(crossings_); ++c) {
      const Crossing& x = at(crossings_, c);
      const auto& ev = at(edges_, x.edge);
      const int a = ev[static_cast<std::size_t>(x.a_end)],
                b = ev[static_cast<std::size_t>(1 - x.a_end)];
      const Eigen::Vector3d d = at(verts_, b).rest - at(verts_, a).rest;
      Eigen::Vector3d n = sheetNormal(x.copy[x.a_end]);
      if (!(n.dot(d) > 0.0)) n = d.normalized();  // the plane must separate a from b
      const Eigen::Vector3d& X = at(verts_, x.copy[0]).rest;
      addPlane(a, X, n);
      addPlane(x.copy[x.a_end], X, n);
      addPlane(b, X, -n);
      addPlane(x.copy[1 - x.a_end], X, -n);
      to_remap.insert(to_remap.end(), {a, b, x.copy[0], x.copy[1]});
    }
    for (int v : created) {
      const int t = at(verts_, v).twin;
      if (t < 0) continue;  // new transient vertex
      const Eigen::Vector3d n = sheetNormal(v);
      addPlane(v, at(verts_, v).rest, n.squaredNorm() > 0.0 ? n : Eigen::Vector3d(-sheetNormal(t)));
    }
    to_remap.insert(to_remap.end(), created.begin(), created.end());
    if (completed_) {
      for (int v : front_) freeVertex(v);
      freeVertex(tip_vertex_[0]);
      freeVertex(tip_vertex_[1]);
      commit();
      out.completed = true;
    } else {
      to_remap.insert(to_remap.end(), front_.begin(), front_.end());
      to_remap.insert(to_remap.end(), tip_vertex_.begin(), tip_vertex_.end());
      if (!pierced) {  // the blade left the cut: keep it as a crack
        commit();
        out.crack = true;
      }
    }
  }
  // Existing vertices first, so new ones see mapped neighbours.
  std::vector<int> done;
  vertex_mark_.resize(verts_.size(), 0);
  for (int v : to_remap) {
    if (!at(verts_, v).used || at(vertex_mark_, v)) continue;
    remap(v);
    at(vertex_mark_, v) = 1;
    done.push_back(v);
  }
  for (int v : done) at(vertex_mark_, v) = 0;
  std::sort(done.begin(), done.end());
  out.remapped = std::move(done);
  return out;
}

}  // namespace surgical_sim::core
