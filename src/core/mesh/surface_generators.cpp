#include "surgical_sim/core/mesh/surface_generators.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {
namespace {

/// The regular icosahedron on the unit sphere, faces counter-clockwise seen from outside.
TriMesh icosahedron() {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriMesh m;
  m.vertices.resize(3, 12);
  m.vertices << -1, 1, -1, 1, 0, 0, 0, 0, t, t, -t, -t,  //
      t, t, -t, -t, -1, 1, -1, 1, 0, 0, 0, 0,            //
      0, 0, 0, 0, t, t, -t, -t, -1, 1, -1, 1;
  m.vertices.colwise().normalize();
  m.triangles.resize(3, 20);
  m.triangles << 0, 0, 0, 0, 0, 1, 5, 11, 10, 7, 3, 3, 3, 3, 3, 4, 2, 6, 8, 9,  //
      11, 5, 1, 7, 10, 5, 11, 10, 7, 1, 9, 4, 2, 6, 8, 9, 4, 2, 6, 8,           //
      5, 1, 7, 10, 11, 9, 4, 2, 6, 8, 4, 2, 6, 8, 9, 5, 11, 10, 7, 1;
  return m;
}

/// Splits every triangle of `m` into 4 at its edge midpoints, projected onto the unit sphere.
TriMesh subdivide(const TriMesh& m) {
  std::vector<Eigen::Vector3d> vertices;
  for (Eigen::Index v = 0; v < m.vertices.cols(); ++v) vertices.push_back(m.vertices.col(v));
  std::unordered_map<std::uint64_t, int> midpoint_of;  // edge (lower, higher) -> vertex
  const auto midpoint = [&](int a, int b) {
    const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) |
                              static_cast<std::uint32_t>(std::max(a, b));
    const auto [it, added] = midpoint_of.emplace(key, static_cast<int>(vertices.size()));
    if (added) vertices.push_back((m.vertices.col(a) + m.vertices.col(b)).normalized());
    return it->second;
  };
  TriMesh out;
  out.triangles.resize(3, 4 * m.triangles.cols());
  for (Eigen::Index t = 0; t < m.triangles.cols(); ++t) {
    const int a = m.triangles(0, t), b = m.triangles(1, t), c = m.triangles(2, t);
    const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    out.triangles.col(4 * t) << a, ab, ca;
    out.triangles.col(4 * t + 1) << ab, b, bc;
    out.triangles.col(4 * t + 2) << ca, bc, c;
    out.triangles.col(4 * t + 3) << ab, bc, ca;
  }
  out.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t v = 0; v < vertices.size(); ++v)
    out.vertices.col(static_cast<Eigen::Index>(v)) = vertices[v];
  return out;
}

void requireSubdivisions(const std::string& function, int subdivisions) {
  if (subdivisions < 0 || subdivisions > kMaxSurfaceSubdivisions) {
    throw std::invalid_argument(function + ": subdivisions = " + std::to_string(subdivisions) +
                                " is out of range: must be in [0, " +
                                std::to_string(kMaxSurfaceSubdivisions) + "]");
  }
}

}  // namespace

TriMesh makeIcosphere(int subdivisions) {
  requireSubdivisions("makeIcosphere", subdivisions);
  TriMesh m = icosahedron();
  for (int s = 0; s < subdivisions; ++s) m = subdivide(m);
  return m;
}

TriMesh makeLiverSurface(const Eigen::Vector3d& semi_axes, int subdivisions) {
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a)
    requirePositive(std::string("makeLiverSurface: semi_axes.") + axes[a], semi_axes[a], "m");
  requireSubdivisions("makeLiverSurface", subdivisions);
  TriMesh m = makeIcosphere(subdivisions);
  for (Eigen::Index v = 0; v < m.vertices.cols(); ++v) {
    const Eigen::Vector3d u = m.vertices.col(v);
    const double notch_x = (u.x() + 0.25) / 0.2;
    Eigen::Vector3d p = u * (1.0 - 0.2 * std::exp(-notch_x * notch_x) * (1.0 + u.z()) / 2.0);
    p.z() = (0.65 + 0.35 * p.x()) * (p.z() + 0.35 * p.z() * p.z()) / 1.35;
    p.y() -= 0.25 * p.x() * p.x();
    m.vertices.col(v) = semi_axes.cwiseProduct(p);
  }
  return m;
}

}  // namespace surgical_sim::core
