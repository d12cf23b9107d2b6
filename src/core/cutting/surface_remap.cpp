#include "surgical_sim/core/cutting/surface_remap.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

#include "surgical_sim/core/tissue/efg_model.h"

namespace surgical_sim::core {

namespace {

/// Grid cells per IP (about) and search radius in cells.
constexpr double kIpsPerCell = 4.0;
constexpr double kSearchCells = 1.0;

/// True when X lies strictly below every plane.
bool belowPlanes(const Eigen::Vector3d& X, const std::vector<CutPlane>& planes) {
  for (const CutPlane& p : planes)
    if ((X - p.point).dot(p.normal) >= 0.0) return false;
  return true;
}

bool shareParticle(const std::vector<int>& a, const std::vector<int>& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (a[i] == b[j]) return true;
    if (a[i] < b[j])
      ++i;
    else
      ++j;
  }
  return false;
}

}  // namespace

int EfgModelSource::numIntegrationPoints() const { return model_.numIntegrationPoints(); }

int EfgModelSource::numParticles() const { return model_.numNodes(); }

Eigen::Vector3d EfgModelSource::particleRestPosition(int p) const {
  return model_.grid().particles.col(p);
}

Eigen::Vector3d EfgModelSource::ipRestPosition(int ip) const {
  return model_.grid().integration_points.col(ip);
}

Eigen::Vector3d EfgModelSource::ipPosition(int ip) const { return ipPositionAt(ip, x_); }

Eigen::Vector3d EfgModelSource::ipPositionAt(int ip, const Eigen::VectorXd& x) const {
  const std::vector<int>& particles = model_.ipParticles(ip);
  const auto phi = model_.shapeValues(ip);
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t a = 0; a < particles.size(); ++a)
    p += phi[static_cast<Eigen::Index>(a)] * x.segment<3>(3 * particles[a]);
  return p;
}

double EfgModelSource::ipWeightNorm(int ip) const { return model_.shapeValues(ip).lpNorm<1>(); }

const std::vector<int>& EfgModelSource::ipParticles(int ip) const { return model_.ipParticles(ip); }

void EfgModelSource::pointWeights(int ip, const Eigen::Vector3d& X, std::vector<int>& particles,
                                  std::vector<double>& weights) const {
  model_.pointWeights(ip, X, particles, weights);
}

SurfaceRemapper::SurfaceRemapper(const EfgMappingSource& source) : source_(source) {
  const int n = source.numIntegrationPoints();
  if (n <= 0)
    throw std::invalid_argument("SurfaceRemapper: numIntegrationPoints() = " + std::to_string(n) +
                                ", must be >= 1");
  ip_rest_.resize(static_cast<std::size_t>(n));
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d X = source.ipRestPosition(i);
    if (!X.allFinite())
      throw std::invalid_argument("SurfaceRemapper: ipRestPosition(" + std::to_string(i) +
                                  ") is not finite");
    ip_rest_[static_cast<std::size_t>(i)] = X;
    lo = lo.cwiseMin(X);
    hi = hi.cwiseMax(X);
  }
  const Eigen::Vector3d extent = (hi - lo).cwiseMax(1e-9 * std::max(1.0, (hi - lo).maxCoeff()));
  cell_ = std::cbrt(kIpsPerCell * extent.prod() / n);
  cell_ = std::max(cell_, extent.maxCoeff() / 256.0);
  origin_ = lo;
  dims_ = ((extent / cell_).array().floor().cast<int>() + 1).matrix();
  cell_start_.assign(static_cast<std::size_t>(dims_.prod()) + 1, 0);
  const auto cellOf = [this](const Eigen::Vector3d& X) { return cellIndex(cellAt(X)); };
  for (const auto& X : ip_rest_) ++cell_start_[static_cast<std::size_t>(cellOf(X)) + 1];
  for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  cell_ips_.resize(ip_rest_.size());
  std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (int i = 0; i < n; ++i)
    cell_ips_[static_cast<std::size_t>(
        fill[static_cast<std::size_t>(cellOf(ip_rest_[static_cast<std::size_t>(i)]))]++)] = i;
}

template <class F>
void SurfaceRemapper::forIpsInCells(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi,
                                    const F& f) const {
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int x = lo.x(); x <= hi.x(); ++x) {
        const Eigen::Vector3i c(x, y, z);
        const auto k = static_cast<std::size_t>(cellIndex(c));
        for (int i = cell_start_[k]; i < cell_start_[k + 1]; ++i)
          f(c, cell_ips_[static_cast<std::size_t>(i)]);
      }
}

std::vector<int> SurfaceRemapper::candidates(const Eigen::Vector3d& X, double radius) const {
  std::vector<std::pair<double, int>> found;
  forIpsInCells(cellAt((X.array() - radius).matrix()), cellAt((X.array() + radius).matrix()),
                [&](const Eigen::Vector3i&, int ip) {
                  const double d2 = (ip_rest_[static_cast<std::size_t>(ip)] - X).squaredNorm();
                  if (d2 <= radius * radius) found.emplace_back(d2, ip);
                });
  std::sort(found.begin(), found.end());
  std::vector<int> out;
  out.reserve(found.size());
  for (const auto& f : found) out.push_back(f.second);
  return out;
}

bool SurfaceRemapper::valid(int ip, const Eigen::Vector3d& X, const Eigen::Vector3d& normal,
                            const std::vector<CutPlane>& planes, const std::vector<int>& ring_ips,
                            int level) const {
  const Eigen::Vector3d& Xi = ip_rest_[static_cast<std::size_t>(ip)];
  if (!belowPlanes(Xi, planes)) return false;
  const bool tangent = level == 0 || level == 2;
  const bool shared = level <= 1;
  if (tangent && (Xi - X).dot(normal) >= 0.0 && normal.squaredNorm() > 0.0) return false;
  if (shared) {
    const std::vector<int>& mine = source_.ipParticles(ip);
    for (int r : ring_ips)
      if (r >= 0 && !shareParticle(mine, source_.ipParticles(r))) return false;
  }
  return true;
}

std::vector<int> SurfaceRemapper::nearby(const Eigen::Vector3d& X) const {
  return candidates(X, kSearchCells * cell_);
}

RemapResult SurfaceRemapper::find(const Eigen::Vector3d& X, const Eigen::Vector3d& normal,
                                  const std::vector<CutPlane>& planes,
                                  const std::vector<int>& ring_ips) const {
  return find(X, normal, planes, ring_ips, nearby(X));
}

RemapResult SurfaceRemapper::find(const Eigen::Vector3d& X, const Eigen::Vector3d& normal,
                                  const std::vector<CutPlane>& planes,
                                  const std::vector<int>& ring_ips,
                                  const std::vector<int>& near) const {
  for (int level = 0; level <= 3; ++level)
    for (int ip : near)
      if (valid(ip, X, normal, planes, ring_ips, level))
        return {ip, static_cast<RemapRelaxation>(level)};
  // Every level needs the cut planes: the IPs below them, nearest first (the order of a search
  // over every IP), from the grid cells not wholly on or above one of the planes; without a
  // valid one, the nearest IP (a sliver between cuts).
  std::vector<std::pair<double, int>> below;
  collectBelow(Eigen::Vector3i::Zero(), dims_, X, planes, below);
  std::sort(below.begin(), below.end());
  for (int level = 0; level <= 3; ++level)
    for (const auto& [d2, ip] : below)
      if (valid(ip, X, normal, planes, ring_ips, level))
        return {ip, static_cast<RemapRelaxation>(level)};
  return {nearest(X), RemapRelaxation::kNearest};
}

Eigen::Vector3i SurfaceRemapper::cellAt(const Eigen::Vector3d& X) const {
  return ((X - origin_) / cell_).array().floor().cast<int>().max(0).min(dims_.array() - 1);
}

int SurfaceRemapper::cellIndex(const Eigen::Vector3i& c) const {
  return (c.z() * dims_.y() + c.y()) * dims_.x() + c.x();
}

void SurfaceRemapper::collectBelow(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi,
                                   const Eigen::Vector3d& X, const std::vector<CutPlane>& planes,
                                   std::vector<std::pair<double, int>>& below) const {
  // (X - point) . normal over the box lies within centre's value +- reach; a margin of 1e-9 cell
  // absorbs round-off. A box wholly on or above a plane holds no IP below them all; a plane the
  // box lies wholly below needs no test inside it.
  const Eigen::Vector3d half = 0.5 * cell_ * (hi - lo).cast<double>();
  const Eigen::Vector3d centre = origin_ + cell_ * lo.cast<double>() + half;
  const double margin = 1e-9 * cell_;
  std::vector<CutPlane> straddling;
  for (const CutPlane& p : planes) {
    const double h = (centre - p.point).dot(p.normal), reach = half.dot(p.normal.cwiseAbs());
    if (h - reach > margin) return;
    if (h + reach >= -margin) straddling.push_back(p);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  if (!straddling.empty() && hi[axis] - lo[axis] > 1) {
    Eigen::Vector3i mid = hi;
    mid[axis] = (lo[axis] + hi[axis]) / 2;
    collectBelow(lo, mid, X, straddling, below);
    Eigen::Vector3i upper = lo;
    upper[axis] = mid[axis];
    collectBelow(upper, hi, X, straddling, below);
    return;
  }
  forIpsInCells(lo, hi - Eigen::Vector3i::Ones(), [&](const Eigen::Vector3i&, int ip) {
    const Eigen::Vector3d& Xi = ip_rest_[static_cast<std::size_t>(ip)];
    if (belowPlanes(Xi, straddling)) below.emplace_back((Xi - X).squaredNorm(), ip);
  });
}

int SurfaceRemapper::nearest(const Eigen::Vector3d& X) const {
  // Cubes of cells of growing half-width r about X's (clamped) cell until no cell outside the
  // cube can hold a nearer IP; ties go to the lower index (as a scan over every IP).
  const Eigen::Vector3i c0 = cellAt(X);
  int best = -1;
  double best_d2 = INFINITY;
  for (int r = 0;; ++r) {
    const Eigen::Vector3i lo = (c0.array() - r).max(0),
                          hi = (c0.array() + r).min(dims_.array() - 1);
    forIpsInCells(lo, hi, [&](const Eigen::Vector3i& c, int ip) {
      if ((c - c0).cwiseAbs().maxCoeff() != r) return;  // visited with a smaller r
      const double d2 = (ip_rest_[static_cast<std::size_t>(ip)] - X).squaredNorm();
      if (d2 < best_d2 || (d2 == best_d2 && ip < best)) {
        best_d2 = d2;
        best = ip;
      }
    });
    // Distance from X to the cells outside the cube (only sides with cells beyond them).
    double bound = INFINITY;
    for (int d = 0; d < 3; ++d) {
      if (lo[d] > 0) bound = std::min(bound, std::max(0.0, X[d] - (origin_[d] + cell_ * lo[d])));
      if (hi[d] < dims_[d] - 1)
        bound = std::min(bound, std::max(0.0, origin_[d] + cell_ * (hi[d] + 1) - X[d]));
    }
    if (std::isinf(bound)) return best;  // every cell visited
    const double margin = bound - 1e-9 * cell_;
    if (best >= 0 && margin > 0.0 && best_d2 < margin * margin) return best;
  }
}

}  // namespace surgical_sim::core
