#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <numeric>
#include <vector>

#include "surgical_sim/core/cutting/blade_sweep.h"
#include "surgical_sim/core/cutting/surface_remap.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/surface.h"
#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core::efg_surface_test {

/// A fake EFG model: particles on a regular grid of spacing h from `lo`, one IP at the centre of
/// each grid cell using the cell's 8 corners with trilinear weights (a partition of unity that
/// reproduces linear fields, extrapolated linearly outside the cell). Static (ipPosition = rest)
/// unless `current` is set.
class GridSource : public EfgMappingSource {
 public:
  GridSource(const Eigen::Vector3d& lo, const Eigen::Vector3i& cells, double h)
      : lo_(lo), cells_(cells), h_(h) {
    for (int k = 0; k < cells.z(); ++k)
      for (int j = 0; j < cells.y(); ++j)
        for (int i = 0; i < cells.x(); ++i) {
          std::vector<int> p;
          for (int c = 0; c < 8; ++c)
            p.push_back(particle(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2)));
          std::sort(p.begin(), p.end());
          particles_.push_back(p);
          corner_.push_back({i, j, k});
        }
  }
  int numParticles() const override {
    return (cells_.x() + 1) * (cells_.y() + 1) * (cells_.z() + 1);
  }
  Eigen::Vector3d particleRestPosition(int p) const override {
    const int nx = cells_.x() + 1, ny = cells_.y() + 1;
    return lo_ + h_ * Eigen::Vector3d(p % nx, (p / nx) % ny, p / (nx * ny));
  }
  int numIntegrationPoints() const override { return static_cast<int>(particles_.size()); }
  Eigen::Vector3d ipRestPosition(int ip) const override {
    return lo_ + h_ * (corner_[static_cast<std::size_t>(ip)].cast<double>().array() + 0.5).matrix();
  }
  /// At rest, or at the mean of its particles' positions in *current when set.
  Eigen::Vector3d ipPosition(int ip) const override {
    return current ? ipPositionAt(ip, *current) : ipRestPosition(ip);
  }
  /// The mean of its particles' positions (at rest: the cell centre).
  Eigen::Vector3d ipPositionAt(int ip, const Eigen::VectorXd& x) const override {
    const std::vector<int>& p = particles_[static_cast<std::size_t>(ip)];
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int a : p) sum += x.segment<3>(3 * a);
    return sum / static_cast<double>(p.size());
  }
  double ipWeightNorm(int) const override { return 1.0; }
  const std::vector<int>& ipParticles(int ip) const override {
    return particles_[static_cast<std::size_t>(ip)];
  }
  void pointWeights(int ip, const Eigen::Vector3d& X, std::vector<int>& particles,
                    std::vector<double>& weights) const override {
    const Eigen::Vector3i c = corner_[static_cast<std::size_t>(ip)];
    const Eigen::Vector3d u = (X - lo_) / h_ - c.cast<double>();
    // The trilinear weights of the IP's cell on the IP's particles (its cell's corners, in
    // order, until a volume cut replaces them).
    particles = particles_[static_cast<std::size_t>(ip)];
    weights.clear();
    for (int n = 0; n < 8; ++n) {
      const int a = n & 1, b = n >> 1 & 1, d = n >> 2;
      weights.push_back((a ? u.x() : 1 - u.x()) * (b ? u.y() : 1 - u.y()) *
                        (d ? u.z() : 1 - u.z()));
    }
  }
  /// Particle positions the IPs follow (nullptr: the IPs stay at rest).
  const Eigen::VectorXd* current = nullptr;
  /// Replaces IP ip's particle set (a volume cut).
  void setParticles(int ip, std::vector<int> p) {
    particles_[static_cast<std::size_t>(ip)] = std::move(p);
  }

 private:
  int particle(int i, int j, int k) const {
    return i + (cells_.x() + 1) * (j + (cells_.y() + 1) * k);
  }
  Eigen::Vector3d lo_;
  Eigen::Vector3i cells_;
  double h_;
  std::vector<std::vector<int>> particles_;
  std::vector<Eigen::Vector3i> corner_;
};

/// Closed outward surface of the box [lo, lo + size] with `cells` grid cells, compact vertices.
inline TriMesh boxSurface(const Eigen::Vector3d& lo, const Eigen::Vector3d& size,
                          const Eigen::Vector3i& cells) {
  const TetMesh mesh = makeBox(lo, size, cells, ElementType::Tet4);
  const SurfaceMesh s = extractSurface(mesh);
  std::vector<int> index(static_cast<std::size_t>(mesh.nodes.cols()), -1);
  TriMesh out;
  out.vertices.resize(3, static_cast<Eigen::Index>(s.nodes.size()));
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    index[static_cast<std::size_t>(s.nodes[i])] = static_cast<int>(i);
    out.vertices.col(static_cast<Eigen::Index>(i)) = mesh.nodes.col(s.nodes[i]);
  }
  out.triangles.resize(3, s.triangles.cols());
  for (Eigen::Index t = 0; t < s.triangles.cols(); ++t)
    for (int k = 0; k < 3; ++k)
      out.triangles(k, t) = index[static_cast<std::size_t>(s.triangles(k, t))];
  return out;
}

/// Connected component of every vertex (by shared triangles); -1 for vertices in no triangle.
inline std::vector<int> components(int vertices, const Eigen::Matrix3Xi& tris, int& count) {
  std::vector<int> parent(static_cast<std::size_t>(vertices));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v)
      v = parent[static_cast<std::size_t>(v)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    return v;
  };
  std::vector<char> used(static_cast<std::size_t>(vertices), 0);
  for (Eigen::Index t = 0; t < tris.cols(); ++t)
    for (int k = 0; k < 3; ++k) {
      used[static_cast<std::size_t>(tris(k, t))] = 1;
      parent[static_cast<std::size_t>(find(tris(k, t)))] = find(tris((k + 1) % 3, t));
    }
  std::vector<int> id(static_cast<std::size_t>(vertices), -1),
      root_id(static_cast<std::size_t>(vertices), -1);
  count = 0;
  for (int v = 0; v < vertices; ++v) {
    if (!used[static_cast<std::size_t>(v)]) continue;
    int& r = root_id[static_cast<std::size_t>(find(v))];
    if (r < 0) r = count++;
    id[static_cast<std::size_t>(v)] = r;
  }
  return id;
}

/// Straight blade along y over [y0, y1] in the plane x = x_cut, at height z (plus tilt * y),
/// moving from height z0 to z1 within one step.
inline BladeSweep verticalSweep(double x_cut, double y0, double y1, double z0, double z1,
                                double tilt) {
  BladeSweep s;
  s.start.resize(3, 2);
  s.end.resize(3, 2);
  s.start << x_cut, x_cut, y0, y1, z0 + tilt * y0, z0 + tilt * y1;
  s.end << x_cut, x_cut, y0, y1, z1 + tilt * y0, z1 + tilt * y1;
  return s;
}

}  // namespace surgical_sim::core::efg_surface_test
