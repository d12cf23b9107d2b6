#include "surgical_sim/core/cutting/efg_volume_cutter.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <stdexcept>
#include <string>
#include <utility>

#include "efg_sweep_slab.h"
#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/cutting/edge_sweep_ccd.h"
#include "surgical_sim/core/tissue/efg_shape_functions.h"

namespace surgical_sim::core {
namespace {

// Largest accepted condition number of a re-selected IP's scaled moment matrix [-].
constexpr double kSelectionCondition = 1e8;
// Side of a broad-phase block in particle spacings (2 d) [-].
constexpr int kBlockParticles = 2;
// Round-off of the broad phase's displacement bound, relative to the largest coordinate [-].
constexpr double kBoundRoundOff = 1e-12;
// Lumped mass below which a particle counts as unused, relative to the total (round-off of the
// removed shares) [-].
constexpr double kUnusedMassFraction = 1e-14;
// Visible particles a re-selection considers at most [-].
constexpr int kMaxCandidates = 4 * EfgOptions::kMaxNeighbours;

// Points of a re-selection: at most EfgOptions::kMaxNeighbours, no heap allocation [m].
using SelectedPoints =
    Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::ColMajor, 3, EfgOptions::kMaxNeighbours>;

// Affine rank (0 to 3) of points (3 x k) at relative tolerance 1e-9 of `scale` [m].
template <class Points>
int affineRank(const Points& points, double scale) {
  if (points.cols() < 2) return 0;
  using Centred =
      Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::ColMajor, 3, Points::MaxColsAtCompileTime>;
  const Centred q = points.colwise() - points.rowwise().mean();
  const Eigen::JacobiSVD<Centred> svd(q);
  return static_cast<int>((svd.singularValues().array() > 1e-9 * scale).count());
}

void requirePositions(const char* name, const Eigen::VectorXd& x, int n) {
  if (x.size() != 3 * n) {
    throw std::invalid_argument(std::string("EfgVolumeCutter::cut: ") + name + " has size " +
                                std::to_string(x.size()) +
                                ", expected 3 n = " + std::to_string(3 * n));
  }
  if (!x.allFinite())
    throw std::invalid_argument(std::string("EfgVolumeCutter::cut: ") + name + " is not finite");
}

}  // namespace

struct EfgVolumeCutter::Selection {
  std::vector<int> particles;
  std::vector<double> distances;  ///< graph distances [m]
  int nearest_ip = -1;            ///< nearest other IP with volume reached in the search
  std::vector<int> links;         ///< the links of the settled nodes' shortest paths
};

EfgVolumeCutter::EfgVolumeCutter(EfgModel& model)
    : model_(model),
      graph_(model),
      samples_(std::max(4, model.options().volume_samples)),
      sample_masks_(static_cast<size_t>(model.numIntegrationPoints())),
      has_indirect_(static_cast<size_t>(model.numIntegrationPoints()), 0),
      search_links_(static_cast<size_t>(model.numIntegrationPoints())),
      searchers_(graph_.links().size()),
      search_dirty_(static_cast<size_t>(model.numIntegrationPoints()), 0) {
  // Broad-phase blocks: the cubes of kBlockParticles particle spacings holding a particle.
  const EfgGrid& grid = model.grid();
  const int n = graph_.numParticles();
  std::vector<Eigen::Vector3i> cube(static_cast<size_t>(n));
  Eigen::Vector3i cubes = Eigen::Vector3i::Ones();
  for (int p = 0; p < n; ++p) {
    const Eigen::Vector3i index =
        ((grid.particles.col(p) - grid.origin) / (2.0 * grid.spacing)).array().round().cast<int>();
    cube[static_cast<size_t>(p)] = (index / kBlockParticles).cwiseMax(0);
    cubes = cubes.cwiseMax(cube[static_cast<size_t>(p)] + Eigen::Vector3i::Ones());
  }
  std::vector<int> block_of_cube(static_cast<size_t>(cubes.prod()), -1);
  particle_block_.resize(static_cast<size_t>(n));
  for (int p = 0; p < n; ++p) {
    const Eigen::Vector3i& c = cube[static_cast<size_t>(p)];
    int& b = block_of_cube[static_cast<size_t>(c.x() + cubes.x() * (c.y() + cubes.y() * c.z()))];
    if (b < 0) {
      b = static_cast<int>(blocks_.size());
      blocks_.emplace_back();
      blocks_.back().rest_lo.setConstant(std::numeric_limits<double>::infinity());
      blocks_.back().rest_hi.setConstant(-std::numeric_limits<double>::infinity());
    }
    particle_block_[static_cast<size_t>(p)] = b;
  }
  for (int l = 0; l < static_cast<int>(graph_.links().size()); ++l) {
    const EfgTopologyGraph::Link& link = graph_.links()[static_cast<size_t>(l)];
    Block& block = blocks_[static_cast<size_t>(particle_block_[static_cast<size_t>(link.a)])];
    block.links.push_back(l);
    block.particles.push_back(link.a);
    if (link.b < n)
      block.particles.push_back(link.b);
    else
      block.ips.push_back(link.b - n);
    for (const int v : {link.a, link.b}) {
      const Eigen::Vector3d X = v < n ? Eigen::Vector3d(grid.particles.col(v))
                                      : Eigen::Vector3d(grid.integration_points.col(v - n));
      block.rest_lo = block.rest_lo.cwiseMin(X);
      block.rest_hi = block.rest_hi.cwiseMax(X);
    }
  }
  mover_marks_.assign(blocks_.size(), 0);
  ip_bounds_.resize(static_cast<size_t>(model.numIntegrationPoints()));
  for (int e = 0; e < model.numIntegrationPoints(); ++e) refreshIpBound(e);
  for (Block& block : blocks_) {
    for (std::vector<int>* ends : {&block.particles, &block.ips}) {
      std::sort(ends->begin(), ends->end());
      ends->erase(std::unique(ends->begin(), ends->end()), ends->end());
    }
    refreshBlock(block);
  }
  block_motion_.resize(3, 2 * static_cast<Eigen::Index>(blocks_.size()));
  tree_of_.assign(static_cast<size_t>(graph_.numNodes()), -1);
  const int count = graph_.components(labels_);
  volume_ips_.assign(static_cast<size_t>(count), 0);
  for (int e = 0; e < model_.numIntegrationPoints(); ++e)
    if (model_.grid().volumes(e) > 0.0) addVolumeIp(e, 1);
}

Eigen::Vector3i EfgVolumeCutter::cellOf(int e) const {
  const EfgGrid& grid = model_.grid();
  return ((grid.integration_points.col(e) - grid.origin) / grid.spacing)
      .array()
      .floor()
      .cast<int>()
      .cwiseMax(0)
      .cwiseMin(grid.cells.array() - 1)
      .matrix();
}

int EfgVolumeCutter::ipAt(const Eigen::Vector3i& c) const {
  const EfgGrid& grid = model_.grid();
  if ((c.array() < 0).any() || (c.array() >= grid.cells.array()).any()) return -1;
  return grid
      .ip_of_cell[static_cast<size_t>(c.x() + grid.cells.x() * (c.y() + grid.cells.y() * c.z()))];
}

void EfgVolumeCutter::refreshIpBound(int e) {
  const EfgGrid& grid = model_.grid();
  const std::vector<int>& particles = model_.ipParticles(e);
  const Eigen::Map<const Eigen::VectorXd> phi = model_.shapeValues(e);
  IpBound& bound = ip_bounds_[static_cast<size_t>(e)];
  bound.movers.clear();
  Eigen::Vector3d reproduced = Eigen::Vector3d::Zero();  // sum_a phi_a X_a [m]
  for (size_t a = 0; a < particles.size(); ++a) {
    reproduced += phi(static_cast<Eigen::Index>(a)) * grid.particles.col(particles[a]);
    bound.movers.push_back(particle_block_[static_cast<size_t>(particles[a])]);
  }
  std::sort(bound.movers.begin(), bound.movers.end());
  bound.movers.erase(std::unique(bound.movers.begin(), bound.movers.end()), bound.movers.end());
  bound.gain = phi.lpNorm<1>();
  bound.unity_error = std::abs(phi.sum() - 1.0);
  bound.residual = (reproduced - grid.integration_points.col(e)).lpNorm<Eigen::Infinity>();
}

void EfgVolumeCutter::refreshBlock(Block& block) {
  // Each mover listed once (a block's IP ends share most of their movers), by a mark per block.
  if (++mover_mark_ == std::numeric_limits<int>::max()) {  // restart the marks
    std::fill(mover_marks_.begin(), mover_marks_.end(), 0);
    mover_mark_ = 1;
  }
  block.movers.clear();
  const auto add = [&](int b) {
    int& mark = mover_marks_[static_cast<size_t>(b)];
    if (mark == mover_mark_) return;
    mark = mover_mark_;
    block.movers.push_back(b);
  };
  for (const int p : block.particles) add(particle_block_[static_cast<size_t>(p)]);
  block.gain = 1.0;
  block.unity_error = 0.0;
  block.residual = 0.0;
  for (const int e : block.ips) {
    const IpBound& bound = ip_bounds_[static_cast<size_t>(e)];
    for (const int b : bound.movers) add(b);
    block.gain = std::max(block.gain, bound.gain);
    block.unity_error = std::max(block.unity_error, bound.unity_error);
    block.residual = std::max(block.residual, bound.residual);
  }
}

void EfgVolumeCutter::addVolumeIp(int e, int change) {
  int& count = volume_ips_[static_cast<size_t>(labels_[static_cast<size_t>(graph_.ipNode(e))])];
  pieces_ -= count > 0 ? 1 : 0;
  count += change;
  pieces_ += count > 0 ? 1 : 0;
}

void EfgVolumeCutter::splitPieces(const std::vector<int>& severed) {
  // Per old piece, a breadth-first search from the ends of its severed links, one search tree per
  // end; trees that meet merge (union-find over the ends). A tree that runs out of nodes to visit
  // is a new piece (every new piece holds such an end); the search stops once at most one tree
  // of the old piece is still growing: that one keeps the old label.
  std::vector<int> ends;
  for (const int l : severed) {
    const EfgTopologyGraph::Link& link = graph_.links()[static_cast<size_t>(l)];
    ends.push_back(link.a);
    ends.push_back(link.b);
  }
  std::sort(ends.begin(), ends.end(), [&](int a, int b) {
    const int la = labels_[static_cast<size_t>(a)], lb = labels_[static_cast<size_t>(b)];
    return la != lb ? la < lb : a < b;
  });
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  for (size_t first = 0; first < ends.size();) {
    const int old_label = labels_[static_cast<size_t>(ends[first])];
    size_t last = first;
    while (last < ends.size() && labels_[static_cast<size_t>(ends[last])] == old_label) ++last;
    const int trees = static_cast<int>(last - first);
    std::vector<int> parent(static_cast<size_t>(trees)), frontier(static_cast<size_t>(trees), 1);
    for (int t = 0; t < trees; ++t) parent[static_cast<size_t>(t)] = t;
    const auto root = [&](int t) {
      while (parent[static_cast<size_t>(t)] != t)
        t = parent[static_cast<size_t>(t)] =
            parent[static_cast<size_t>(parent[static_cast<size_t>(t)])];
      return t;
    };
    std::vector<std::pair<int, int>> visited;  // (graph node, tree)
    std::queue<int> queue;
    for (int t = 0; t < trees; ++t) {
      const int v = ends[first + static_cast<size_t>(t)];
      tree_of_[static_cast<size_t>(v)] = t;
      visited.emplace_back(v, t);
      queue.push(v);
    }
    int growing = trees;
    while (growing > 1 && !queue.empty()) {
      const int v = queue.front();
      queue.pop();
      int r = root(tree_of_[static_cast<size_t>(v)]);
      --frontier[static_cast<size_t>(r)];
      for (const int l : graph_.linksOf(v)) {
        if (!graph_.alive(l)) continue;
        const int w = graph_.otherEnd(l, v);
        int& tw = tree_of_[static_cast<size_t>(w)];
        if (tw < 0) {
          tw = r;
          visited.emplace_back(w, r);
          queue.push(w);
          ++frontier[static_cast<size_t>(r)];
        } else if (const int rw = root(tw); rw != r) {
          // Two growing trees meet (a finished tree has no alive link out of it).
          parent[static_cast<size_t>(rw)] = r;
          frontier[static_cast<size_t>(r)] += frontier[static_cast<size_t>(rw)];
          --growing;
        }
      }
      if (frontier[static_cast<size_t>(r)] == 0) --growing;  // r is a whole new piece
    }
    // Finished trees become new pieces; the growing one (if any) keeps the old label.
    std::vector<int> new_label(static_cast<size_t>(trees), -1);
    for (int t = 0; t < trees; ++t) {
      const int r = root(t);
      if (r == t && frontier[static_cast<size_t>(r)] == 0) {
        new_label[static_cast<size_t>(r)] = static_cast<int>(volume_ips_.size());
        volume_ips_.push_back(0);
      }
    }
    const int n = graph_.numParticles();
    for (const auto& [v, t] : visited) {
      tree_of_[static_cast<size_t>(v)] = -1;
      const int label = new_label[static_cast<size_t>(root(t))];
      if (label < 0) continue;
      const bool holds = v >= n && model_.grid().volumes(v - n) > 0.0;
      if (holds) addVolumeIp(v - n, -1);
      labels_[static_cast<size_t>(v)] = label;
      if (holds) addVolumeIp(v - n, 1);
    }
    first = last;
  }
}

std::vector<int> EfgVolumeCutter::unusedParticles() const {
  std::vector<int> unused;
  const double total_mass = model_.lumpedMass().sum() / 3.0;  // [kg]
  for (int p = 0; p < graph_.numParticles(); ++p)
    if (model_.lumpedMass()(3 * p) <= kUnusedMassFraction * total_mass) unused.push_back(p);
  return unused;
}

std::vector<int> EfgVolumeCutter::particlePieces() const {
  return {labels_.begin(), labels_.begin() + graph_.numParticles()};
}

EfgVolumeCutter::Selection EfgVolumeCutter::select(int e) const {
  const EfgGrid& grid = model_.grid();
  const int n = graph_.numParticles();
  const double scale = 2.0 * grid.spacing;
  const Eigen::Vector3d x_e = grid.integration_points.col(e);
  const int target = model_.options().neighbours;
  Selection out;
  SelectedPoints points(3, 0);
  // A set of `target` particles (fewer when no other particle is visible) with a well-conditioned
  // moment matrix.
  const auto accepted = [&](bool exhausted) {
    const int size = static_cast<int>(out.particles.size());
    if (size < 4 || (size < target && !exhausted)) return false;
    Eigen::VectorXd detours(points.cols());
    double r_max = 0.0;
    for (Eigen::Index a = 0; a < points.cols(); ++a) {
      const double r = out.distances[static_cast<size_t>(a)];
      detours(a) = std::max(0.0, r - (points.col(a) - x_e).norm());
      r_max = std::max(r_max, r);
    }
    const MlsShapeFunctions mls = computeMlsShapeFunctions(
        x_e, Eigen::Matrix3Xd(points), model_.options().kernel_support * r_max, detours);
    return mls.status == MlsStatus::Ok && mls.condition <= kSelectionCondition;
  };
  int visited = 0;
  bool ok = false, done = false;
  graph_.searchFrom(graph_.ipNode(e), [&](int v, double r, int link) {
    if (link >= 0) out.links.push_back(link);
    if (v >= n) {
      if (v != graph_.ipNode(e) && out.nearest_ip < 0 && grid.volumes(v - n) > 0.0)
        out.nearest_ip = v - n;
      return true;
    }
    ++visited;
    SelectedPoints with(3, points.cols() + 1);
    with << points, grid.particles.col(v);
    const int size = static_cast<int>(with.cols());
    const int free_places = std::max(target - size, 0);
    if (size >= target || free_places >= 3 || affineRank(with, scale) + free_places >= 3) {
      points = with;
      out.particles.push_back(v);
      out.distances.push_back(r);
      ok = accepted(false);
      done = ok || size == EfgOptions::kMaxNeighbours;
    }
    return !done && visited < kMaxCandidates;
  });
  if (!done) ok = accepted(true);  // every visible particle seen
  if (!ok) {
    out.particles.clear();
    out.distances.clear();
  }
  return out;
}

bool EfgVolumeCutter::holds(int e, const Selection& selection) const {
  const EfgGrid& grid = model_.grid();
  std::vector<std::pair<int, double>> now, before;
  for (size_t a = 0; a < selection.particles.size(); ++a)
    now.emplace_back(selection.particles[a], selection.distances[a]);
  std::sort(now.begin(), now.end());
  const std::vector<int>& old = model_.ipParticles(e);
  const Eigen::Map<const Eigen::VectorXd> detours = model_.detours(e);
  for (size_t a = 0; a < old.size(); ++a)
    before.emplace_back(old[a],
                        (grid.particles.col(old[a]) - grid.integration_points.col(e)).norm() +
                            detours(static_cast<Eigen::Index>(a)));
  bool same = now.size() == before.size();
  for (size_t a = 0; same && a < now.size(); ++a)
    same = now[a].first == before[a].first &&
           std::abs(now[a].second - before[a].second) <= 1e-12 * grid.spacing;
  return same;
}

std::vector<int> EfgVolumeCutter::staleNeighbourhoods() const {
  std::vector<int> stale;
  for (int e = 0; e < model_.numIntegrationPoints(); ++e) {
    if (search_links_[static_cast<size_t>(e)].empty() || !(model_.grid().volumes(e) > 0.0))
      continue;
    const Selection selection = select(e);
    if (!selection.particles.empty() && !holds(e, selection)) stale.push_back(e);
  }
  return stale;
}

EfgCutResult EfgVolumeCutter::cut(const BladeSweep& sweep, const Eigen::VectorXd& x_start,
                                  const Eigen::VectorXd& x_end) {
  validateBladeSweep(sweep);
  const int n = graph_.numParticles();
  requirePositions("x_start", x_start, n);
  requirePositions("x_end", x_end, n);
  const EfgGrid& grid = model_.grid();
  EfgCutResult result;
  const Stopwatch detect;

  // 1. Broad phase: the blocks whose ends' reach (their rest box grown by the bound on their
  // displacement) meets the box and slab of a segment's sweep, then those of their alive links
  // whose motion box meets the sweep's box.
  const double tolerance = 1e-9 * grid.spacing;  // [m]
  const Eigen::AlignedBox3d sweep_box = sweepBox(sweep, tolerance);
  const Eigen::Vector3d sweep_lo = sweep_box.min(), sweep_hi = sweep_box.max();
  std::vector<efg_sweep_slab::SweepSlab> slabs;
  std::vector<std::array<Eigen::Vector3d, 2>> segment_boxes;  // (lower, upper corner) [m]
  for (Eigen::Index i = 0; i + 1 < sweep.start.cols(); ++i) {
    slabs.push_back(efg_sweep_slab::sweepSlab(sweep, i, tolerance));
    const Eigen::Vector3d lo = sweep.start.col(i)
                                   .cwiseMin(sweep.start.col(i + 1))
                                   .cwiseMin(sweep.end.col(i).cwiseMin(sweep.end.col(i + 1)));
    const Eigen::Vector3d hi = sweep.start.col(i)
                                   .cwiseMax(sweep.start.col(i + 1))
                                   .cwiseMax(sweep.end.col(i).cwiseMax(sweep.end.col(i + 1)));
    segment_boxes.push_back({lo.array() - tolerance, hi.array() + tolerance});
  }
  // Positions of graph node v at the step start (end = 0) or end (1); an IP's are computed once
  // a call.
  ++calls_;
  ip_x_call_.resize(static_cast<size_t>(model_.numIntegrationPoints()), 0);
  ip_x_.resize(3, 2 * model_.numIntegrationPoints());
  const auto position = [&](int v, int end) -> Eigen::Vector3d {
    if (v < n) return (end ? x_end : x_start).segment<3>(3 * v);
    const int e = v - n;
    if (ip_x_call_[static_cast<size_t>(e)] != calls_) {
      ip_x_call_[static_cast<size_t>(e)] = calls_;
      const std::vector<int>& particles = model_.ipParticles(e);
      const Eigen::Map<const Eigen::VectorXd> phi = model_.shapeValues(e);
      Eigen::Vector3d sum[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
      for (size_t a = 0; a < particles.size(); ++a) {
        const double w = phi(static_cast<Eigen::Index>(a));
        sum[0] += w * x_start.segment<3>(3 * particles[a]);
        sum[1] += w * x_end.segment<3>(3 * particles[a]);
      }
      ip_x_.col(2 * e) = sum[0];
      ip_x_.col(2 * e + 1) = sum[1];
    }
    return ip_x_.col(2 * e + end);
  };
  // Link l's ends at the step start and end: a (start), b (start), a (end), b (end) [m].
  const auto ends = [&](int l) -> std::array<Eigen::Vector3d, 4> {
    const EfgTopologyGraph::Link& link = graph_.links()[static_cast<size_t>(l)];
    return {position(link.a, 0), position(link.b, 0), position(link.a, 1), position(link.b, 1)};
  };
  // The ends move linearly, so over the step the link stays in the hull of their four
  // positions, and a crossing (a point of the link within `tolerance` of the blade) lies in the
  // sweep's box and in that of the crossed segment: a link whose four positions' box misses
  // either is not crossed there.
  struct LinkBox {
    Eigen::Vector3d lo, hi;
    explicit LinkBox(const std::array<Eigen::Vector3d, 4>& x)
        : lo(x[0].cwiseMin(x[1]).cwiseMin(x[2].cwiseMin(x[3]))),
          hi(x[0].cwiseMax(x[1]).cwiseMax(x[2].cwiseMax(x[3]))) {}
    LinkBox(const Eigen::Vector3d& lower, const Eigen::Vector3d& upper) : lo(lower), hi(upper) {}
    bool misses(const Eigen::Vector3d& a_lo, const Eigen::Vector3d& a_hi) const {
      return (a_hi.array() < lo.array()).any() || (a_lo.array() > hi.array()).any();
    }
  };
  // Per block, the box of its particles' displacements d = x - X at the step start and end
  // (block_motion_ columns 2b: lower, 2b + 1: upper corner), and per link block the box of its
  // movers' (centre c, half-sides h). A particle end then lies within h of X + c and an IP end e,
  // at X_e + c + sum_a phi_a (d_a - c) + (sum_a phi_a - 1) c + (sum_a phi_a X_a - X_e), within
  // L h + u |c| + r of X_e + c (L, u, r: the block's gain, unity error and residual), to
  // round-off of the positions.
  for (Eigen::Index b = 0; b < static_cast<Eigen::Index>(blocks_.size()); ++b) {
    block_motion_.col(2 * b).setConstant(std::numeric_limits<double>::infinity());
    block_motion_.col(2 * b + 1).setConstant(-std::numeric_limits<double>::infinity());
  }
  // Every movers' box lies in the box G of all displacements (lower, upper corner): with
  // L >= 1, c - L h = (c - h) - (L - 1) h >= G_lo - (L - 1) H (H: G's half-sides) and
  // |c| <= C = max(|G_lo|, |G_hi|), so a block whose rest box grown by G and by
  // (L - 1) H + u C + r misses the sweep's box is skipped before its movers are read.
  Eigen::Vector3d all_lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d all_hi = -all_lo;  // [m]
  for (int p = 0; p < n; ++p) {
    const Eigen::Vector3d X = grid.particles.col(p);
    const Eigen::Vector3d d0 = x_start.segment<3>(3 * p) - X, d1 = x_end.segment<3>(3 * p) - X;
    const Eigen::Vector3d lo = d0.cwiseMin(d1), hi = d0.cwiseMax(d1);
    const Eigen::Index b = particle_block_[static_cast<size_t>(p)];
    block_motion_.col(2 * b) = block_motion_.col(2 * b).cwiseMin(lo);
    block_motion_.col(2 * b + 1) = block_motion_.col(2 * b + 1).cwiseMax(hi);
    all_lo = all_lo.cwiseMin(lo);
    all_hi = all_hi.cwiseMax(hi);
  }
  const double round_off =
      kBoundRoundOff * std::max({x_start.lpNorm<Eigen::Infinity>(), x_end.lpNorm<Eigen::Infinity>(),
                                 grid.particles.lpNorm<Eigen::Infinity>()});  // [m]
  const Eigen::Vector3d all_half = 0.5 * (all_hi - all_lo);
  const Eigen::Vector3d all_centre = all_lo.cwiseAbs().cwiseMax(all_hi.cwiseAbs());
  std::vector<int> candidates;
  for (const Block& block : blocks_) {
    const Eigen::Vector3d slack = (block.gain - 1.0) * all_half.array() +
                                  block.unity_error * all_centre.array() + block.residual +
                                  block.gain * round_off;  // [m]
    if (LinkBox(block.rest_lo + all_lo - slack, block.rest_hi + all_hi + slack)
            .misses(sweep_lo, sweep_hi))
      continue;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;  // the movers' displacement box [m]
    for (const int b : block.movers) {
      lo = lo.cwiseMin(block_motion_.col(2 * b));
      hi = hi.cwiseMax(block_motion_.col(2 * b + 1));
    }
    const Eigen::Vector3d c = 0.5 * (lo + hi);
    const Eigen::Vector3d reach = block.gain * (0.5 * (hi - lo)).array() +
                                  block.unity_error * c.array().abs() + block.residual +
                                  block.gain * round_off;  // [m]
    const LinkBox box(block.rest_lo + c - reach, block.rest_hi + c + reach);
    if (box.misses(sweep_lo, sweep_hi)) continue;
    bool near = false;
    for (size_t i = 0; !near && i < slabs.size(); ++i)
      near = !box.misses(segment_boxes[i][0], segment_boxes[i][1]) &&
             slabs[i].boxGap(box.lo, box.hi) == 0.0;
    if (!near) continue;
    // The same bound on each alive link's own rest box first, then its motion box.
    for (const int l : block.links) {
      if (!graph_.alive(l)) continue;
      const EfgTopologyGraph::Link& link = graph_.links()[static_cast<size_t>(l)];
      const Eigen::Vector3d X0 = grid.particles.col(link.a);
      const Eigen::Vector3d X1 = link.b < n
                                     ? Eigen::Vector3d(grid.particles.col(link.b))
                                     : Eigen::Vector3d(grid.integration_points.col(link.b - n));
      if (!LinkBox(X0.cwiseMin(X1) + c - reach, X0.cwiseMax(X1) + c + reach)
               .misses(sweep_lo, sweep_hi) &&
          !LinkBox(ends(l)).misses(sweep_lo, sweep_hi))
        candidates.push_back(l);
    }
  }
  std::map<int, std::vector<Eigen::Vector3d>> crossings;  // IP -> rest crossing points [m]
  std::vector<Eigen::Vector3d> all_crossings;
  std::sort(candidates.begin(), candidates.end());
  for (const int l : candidates) {
    const EfgTopologyGraph::Link& link = graph_.links()[static_cast<size_t>(l)];
    const std::array<Eigen::Vector3d, 4> x = ends(l);
    const auto& [e0s, e1s, e0e, e1e] = x;
    const LinkBox box(x);
    for (Eigen::Index i = 0; i + 1 < sweep.start.cols(); ++i) {
      const auto& segment = segment_boxes[static_cast<size_t>(i)];
      if (box.misses(segment[0], segment[1]) ||
          slabs[static_cast<size_t>(i)].apart({e0s, e1s, e0e, e1e}))
        continue;
      const auto hit =
          edgeSweepCrossing(sweep.start.col(i), sweep.start.col(i + 1), sweep.end.col(i),
                            sweep.end.col(i + 1), e0s, e1s, e0e, e1e, tolerance);
      if (!hit) continue;
      result.severed_links.push_back(l);
      const Eigen::Vector3d X0 = grid.particles.col(link.a);
      const Eigen::Vector3d X1 = link.b < n
                                     ? Eigen::Vector3d(grid.particles.col(link.b))
                                     : Eigen::Vector3d(grid.integration_points.col(link.b - n));
      const Eigen::Vector3d X = X0 + hit->s * (X1 - X0);
      all_crossings.push_back(X);
      if (link.b >= n) crossings[link.b - n].push_back(X);
      break;
    }
  }
  result.detect_seconds = detect.seconds();
  if (result.severed_links.empty()) {
    result.pieces = pieces_;
    return result;
  }
  for (const int l : result.severed_links) graph_.sever(l);

  // 2. Affected IPs: a severed link of their own, or indirect particles near a crossing whose
  // last search reached a node by a link severed since. Severing any other link leaves every
  // settled node's distance (it only lengthens paths, and the settled ones keep theirs), so the
  // search settles the same nodes at the same distances, in the same order, and selects the same.
  std::vector<int> affected;
  for (const auto& entry : crossings) affected.push_back(entry.first);
  for (const int l : result.severed_links)
    for (const int e : searchers_[static_cast<size_t>(l)])
      search_dirty_[static_cast<size_t>(e)] = 1;
  const auto reaches = [&](int e) {
    return search_links_[static_cast<size_t>(e)].empty() || search_dirty_[static_cast<size_t>(e)];
  };
  const int reach = 4;  // integration cells: two DOF cells
  for (const Eigen::Vector3d& X : all_crossings) {
    const Eigen::Vector3i c = ((X - grid.origin) / grid.spacing).array().floor().cast<int>();
    for (int k = -reach; k <= reach; ++k)
      for (int j = -reach; j <= reach; ++j)
        for (int i = -reach; i <= reach; ++i) {
          const int e = ipAt(c + Eigen::Vector3i(i, j, k));
          if (e >= 0 && has_indirect_[static_cast<size_t>(e)] && reaches(e)) affected.push_back(e);
        }
  }
  std::sort(affected.begin(), affected.end());
  affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
  // The volumes this cut changes, over the grid's [m^3].
  std::map<int, double> new_volumes;
  const auto volume = [&](int e) {
    const auto it = new_volumes.find(e);
    return it == new_volumes.end() ? grid.volumes(e) : it->second;
  };
  std::map<int, Selection> selections;
  for (const int e : affected)
    if (grid.volumes(e) > 0.0) selections.emplace(e, select(e));

  const auto nearestAcross = [&](int e, const Eigen::Vector3d& target,
                                 const std::function<bool(int)>& admissible) {
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    const Eigen::Vector3i c = cellOf(e);
    for (int k = -1; k <= 1; ++k)
      for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) {
          const int r = ipAt(c + Eigen::Vector3i(i, j, k));
          if (r < 0 || r == e || volume(r) <= 0.0 || !admissible(r)) continue;
          const auto it = selections.find(r);
          if (it != selections.end() && it->second.particles.empty()) continue;
          const double d = (grid.integration_points.col(r) - target).norm();
          if (d < best_d) {
            best_d = d;
            best = r;
          }
        }
    return best;
  };
  std::vector<std::pair<int, std::vector<char>>> old_masks;  // restored if the cut is rejected
  for (const auto& [e, points] : crossings) {
    if (volume(e) <= 0.0) continue;
    const auto sel = selections.find(e);
    if (sel != selections.end() && sel->second.particles.empty()) continue;  // isolated: below
    Eigen::Matrix3Xd P(3, static_cast<Eigen::Index>(points.size()));
    for (size_t i = 0; i < points.size(); ++i) P.col(static_cast<Eigen::Index>(i)) = points[i];
    const Eigen::Vector3d centre = P.rowwise().mean();
    const Eigen::Vector3d x_e = grid.integration_points.col(e);
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    if (affineRank(P, grid.spacing) >= 2) {
      const Eigen::JacobiSVD<Eigen::MatrixXd> svd(P.colwise() - centre, Eigen::ComputeFullU);
      normal = svd.matrixU().col(2);
    } else {
      for (const Eigen::Vector3d& X : points) normal += (X - x_e).normalized();
    }
    if (!(normal.norm() > 0.0)) continue;
    normal.normalize();
    if (normal.dot(x_e - centre) > 0.0) normal = -normal;  // the IP on the negative side
    std::vector<char>& mask = sample_masks_[static_cast<size_t>(e)];
    old_masks.emplace_back(e, mask);
    const int s3 = samples_ * samples_ * samples_;
    if (mask.empty()) mask.assign(static_cast<size_t>(s3), 1);
    const Eigen::Vector3d corner = grid.origin + grid.spacing * cellOf(e).cast<double>();
    int remaining = 0, far = 0;
    Eigen::Vector3d far_centroid = Eigen::Vector3d::Zero();
    std::vector<int> far_samples;
    for (int q = 0; q < s3; ++q) {
      if (!mask[static_cast<size_t>(q)]) continue;
      ++remaining;
      const Eigen::Vector3d X =
          corner +
          grid.spacing / samples_ *
              (Eigen::Vector3i(q % samples_, (q / samples_) % samples_, q / (samples_ * samples_))
                   .cast<double>() +
               Eigen::Vector3d::Constant(0.5));
      if (normal.dot(X - centre) > 0.0) {
        ++far;
        far_centroid += X;
        far_samples.push_back(q);
      }
    }
    if (far == 0 || far == remaining) continue;
    far_centroid /= far;
    const int receiver = nearestAcross(e, far_centroid, [&](int r) {
      return normal.dot(grid.integration_points.col(r) - centre) > 0.0;
    });
    if (receiver < 0) continue;
    const double moved = volume(e) * far / remaining;  // [m^3]
    const double kept = volume(e) - moved, received = volume(receiver) + moved;
    new_volumes[e] = kept;
    new_volumes[receiver] = received;
    for (const int q : far_samples) mask[static_cast<size_t>(q)] = 0;
  }
  for (const auto& [e, sel] : selections) {
    if (!sel.particles.empty() || volume(e) <= 0.0) continue;
    result.isolated_ips.push_back(e);
    int receiver = sel.nearest_ip;
    if (receiver >= 0) {
      const auto it = selections.find(receiver);
      if (it != selections.end() && it->second.particles.empty()) receiver = -1;
    }
    if (receiver < 0)
      receiver = nearestAcross(e, grid.integration_points.col(e), [](int) { return true; });
    if (receiver < 0) continue;  // nothing to hand the volume to: it stays
    const double received = volume(receiver) + volume(e);
    new_volumes[receiver] = received;
    new_volumes[e] = 0.0;
  }

  // Only re-selected IPs and those whose volume changed can change (ascending).
  std::vector<int> candidate_ips;
  for (const auto& entry : selections) candidate_ips.push_back(entry.first);
  for (const auto& entry : new_volumes) candidate_ips.push_back(entry.first);
  std::sort(candidate_ips.begin(), candidate_ips.end());
  candidate_ips.erase(std::unique(candidate_ips.begin(), candidate_ips.end()), candidate_ips.end());
  std::vector<EfgNeighbourhood> changes;
  for (const int e : candidate_ips) {
    const auto sel = selections.find(e);
    const bool reselected = sel != selections.end() && !sel->second.particles.empty();
    EfgNeighbourhood c;
    c.ip = e;
    c.volume = volume(e);
    if (reselected) {
      c.particles = sel->second.particles;
      c.distances = sel->second.distances;
    } else if (volume(e) != grid.volumes(e)) {
      c.particles = model_.ipParticles(e);
      const Eigen::Map<const Eigen::VectorXd> detours = model_.detours(e);
      for (size_t a = 0; a < c.particles.size(); ++a)
        c.distances.push_back(
            (grid.particles.col(c.particles[a]) - grid.integration_points.col(e)).norm() +
            detours(static_cast<Eigen::Index>(a)));
    } else {
      continue;
    }
    // Unchanged set and distances: nothing to do.
    if (reselected && volume(e) == grid.volumes(e) && holds(e, sel->second)) continue;
    changes.push_back(std::move(c));
  }
  // Particles whose mass the changes can lower (an IP's old particles; an isolated IP's keep
  // their index with volume 0), with the mass they had.
  std::vector<int> touched;
  for (const EfgNeighbourhood& c : changes)
    touched.insert(touched.end(), model_.ipParticles(c.ip).begin(), model_.ipParticles(c.ip).end());
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  const double total_mass = model_.lumpedMass().sum() / 3.0;  // [kg]
  std::vector<char> used_before(touched.size());
  for (size_t i = 0; i < touched.size(); ++i)
    used_before[i] = model_.lumpedMass()(3 * touched[i]) > kUnusedMassFraction * total_mass;
  std::vector<char> held_volume(changes.size());
  for (size_t i = 0; i < changes.size(); ++i)
    held_volume[i] = grid.volumes(changes[i].ip) > 0.0 ? 1 : 0;
  try {
    model_.setNeighbourhoods(changes);
  } catch (...) {
    // Rejected: the model is unchanged (strong guarantee); undo the graph and the volume samples.
    for (const int l : result.severed_links) graph_.restore(l);
    for (auto it = old_masks.rbegin(); it != old_masks.rend(); ++it)
      sample_masks_[static_cast<size_t>(it->first)] = std::move(it->second);
    throw;
  }
  // The broad-phase bounds of the changed IPs and of the blocks holding their links.
  std::vector<int> stale_blocks;
  for (const EfgNeighbourhood& c : changes) refreshIpBound(c.ip);
  for (const EfgNeighbourhood& c : changes)
    for (const int l : graph_.linksOf(graph_.ipNode(c.ip)))
      stale_blocks.push_back(
          particle_block_[static_cast<size_t>(graph_.links()[static_cast<size_t>(l)].a)]);
  std::sort(stale_blocks.begin(), stale_blocks.end());
  stale_blocks.erase(std::unique(stale_blocks.begin(), stale_blocks.end()), stale_blocks.end());
  for (const int b : stale_blocks) refreshBlock(blocks_[static_cast<size_t>(b)]);
  // An isolated IP that kept its volume (no receiver) is retried by every cut near it: its
  // receiver depends on more than its own search.
  for (auto& [e, sel] : selections) {
    std::vector<int>& links = search_links_[static_cast<size_t>(e)];
    for (const int l : links) {
      std::vector<int>& ips = searchers_[static_cast<size_t>(l)];
      *std::find(ips.begin(), ips.end(), e) = ips.back();
      ips.pop_back();
    }
    links = sel.particles.empty() ? std::vector<int>() : std::move(sel.links);
    for (const int l : links) searchers_[static_cast<size_t>(l)].push_back(e);
    search_dirty_[static_cast<size_t>(e)] = 0;
  }
  for (size_t i = 0; i < touched.size(); ++i)
    if (used_before[i] && model_.lumpedMass()(3 * touched[i]) <= kUnusedMassFraction * total_mass)
      result.unused_particles.push_back(touched[i]);
  for (const EfgNeighbourhood& c : changes) {
    result.changed_ips.push_back(c.ip);
    bool indirect = false;
    for (const int p : c.particles) {
      bool linked = false;
      for (const int l : graph_.linksOf(graph_.ipNode(c.ip)))
        linked = linked || (graph_.alive(l) && graph_.otherEnd(l, graph_.ipNode(c.ip)) == p);
      indirect = indirect || !linked;
    }
    has_indirect_[static_cast<size_t>(c.ip)] = indirect ? 1 : 0;
  }
  const int before = pieces_;
  for (size_t i = 0; i < changes.size(); ++i)
    addVolumeIp(changes[i].ip, (grid.volumes(changes[i].ip) > 0.0 ? 1 : 0) - held_volume[i]);
  splitPieces(result.severed_links);
  result.pieces = pieces_;
  result.pieces_changed = pieces_ != before;
  return result;
}

}  // namespace surgical_sim::core
