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

Eigen::Vector3d EfgModelSource::ipRestPosition(int ip) const {
  return model_.grid().integration_points.col(ip);
}

Eigen::Vector3d EfgModelSource::ipPosition(int ip) const {
  const std::vector<int>& particles = model_.ipParticles(ip);
  const auto phi = model_.shapeValues(ip);
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t a = 0; a < particles.size(); ++a)
    p += phi[static_cast<Eigen::Index>(a)] * x_.segment<3>(3 * particles[a]);
  return p;
}

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
  auto cellOf = [this](const Eigen::Vector3d& X) {
    const Eigen::Vector3i c =
        ((X - origin_) / cell_).array().floor().cast<int>().max(0).min(dims_.array() - 1);
    return (c.z() * dims_.y() + c.y()) * dims_.x() + c.x();
  };
  for (const auto& X : ip_rest_) ++cell_start_[static_cast<std::size_t>(cellOf(X)) + 1];
  for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  cell_ips_.resize(ip_rest_.size());
  std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (int i = 0; i < n; ++i)
    cell_ips_[static_cast<std::size_t>(
        fill[static_cast<std::size_t>(cellOf(ip_rest_[static_cast<std::size_t>(i)]))]++)] = i;
}

std::vector<int> SurfaceRemapper::candidates(const Eigen::Vector3d& X, double radius) const {
  std::vector<std::pair<double, int>> found;
  const Eigen::Vector3i c0 = ((X.array() - radius - origin_.array()) / cell_)
                                 .floor()
                                 .cast<int>()
                                 .max(0)
                                 .min(dims_.array() - 1);
  const Eigen::Vector3i c1 = ((X.array() + radius - origin_.array()) / cell_)
                                 .floor()
                                 .cast<int>()
                                 .max(0)
                                 .min(dims_.array() - 1);
  for (int z = c0.z(); z <= c1.z(); ++z)
    for (int y = c0.y(); y <= c1.y(); ++y)
      for (int x = c0.x(); x <= c1.x(); ++x) {
        const auto c = static_cast<std::size_t>((z * dims_.y() + y) * dims_.x() + x);
        for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
          const int ip = cell_ips_[static_cast<std::size_t>(k)];
          const double d2 = (ip_rest_[static_cast<std::size_t>(ip)] - X).squaredNorm();
          if (d2 <= radius * radius) found.emplace_back(d2, ip);
        }
      }
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

RemapResult SurfaceRemapper::find(const Eigen::Vector3d& X, const Eigen::Vector3d& normal,
                                  const std::vector<CutPlane>& planes,
                                  const std::vector<int>& ring_ips) const {
  const std::vector<int> near = candidates(X, kSearchCells * cell_);
  for (int level = 0; level <= 3; ++level)
    for (int ip : near)
      if (valid(ip, X, normal, planes, ring_ips, level))
        return {ip, static_cast<RemapRelaxation>(level)};
  // Every level needs the cut planes: one pass lists the IPs below them (nearest first, the
  // order of a search over every IP) and finds the nearest IP, the answer when none is below
  // them (a sliver between cuts).
  int nearest = 0;
  double nearest_d2 = INFINITY;
  std::vector<std::pair<double, int>> below;
  for (std::size_t i = 0; i < ip_rest_.size(); ++i) {
    const double d2 = (ip_rest_[i] - X).squaredNorm();
    if (d2 < nearest_d2) {
      nearest_d2 = d2;
      nearest = static_cast<int>(i);
    }
    if (belowPlanes(ip_rest_[i], planes)) below.emplace_back(d2, static_cast<int>(i));
  }
  std::sort(below.begin(), below.end());
  for (int level = 0; level <= 3; ++level)
    for (const auto& [d2, ip] : below)
      if (valid(ip, X, normal, planes, ring_ips, level))
        return {ip, static_cast<RemapRelaxation>(level)};
  return {nearest, RemapRelaxation::kNearest};
}

}  // namespace surgical_sim::core
