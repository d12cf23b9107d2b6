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

namespace {

void requireSegments(const std::string& name, int value, int lowest) {
  if (value < lowest || value > kMaxSurfaceSegments) {
    throw std::invalid_argument(name + " = " + std::to_string(value) +
                                " is out of range: must be in [" + std::to_string(lowest) + ", " +
                                std::to_string(kMaxSurfaceSegments) + "]");
  }
}

/// Adds the two outward triangles of each cell of a (columns x rows) vertex grid that wraps
/// around in the column direction (and in the row direction when wrap_rows), vertex (i, j) at
/// index i + columns j, outward = d/di x d/dj.
void addWrappedGrid(int columns, int rows, bool wrap_rows, std::vector<Eigen::Vector3i>& out) {
  const int cell_rows = wrap_rows ? rows : rows - 1;
  for (int j = 0; j < cell_rows; ++j) {
    for (int i = 0; i < columns; ++i) {
      const int i1 = (i + 1) % columns, j1 = (j + 1) % rows;
      const int a = i + columns * j, b = i1 + columns * j;
      const int c = i1 + columns * j1, d = i + columns * j1;
      out.emplace_back(a, b, c);
      out.emplace_back(a, c, d);
    }
  }
}

TriMesh toMesh(const std::vector<Eigen::Vector3d>& vertices,
               const std::vector<Eigen::Vector3i>& triangles) {
  TriMesh m;
  m.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (size_t v = 0; v < vertices.size(); ++v)
    m.vertices.col(static_cast<Eigen::Index>(v)) = vertices[v];
  m.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (size_t t = 0; t < triangles.size(); ++t)
    m.triangles.col(static_cast<Eigen::Index>(t)) = triangles[t];
  return m;
}

}  // namespace

TriMesh makeCylinder(double radius, double length, int segments, int rings) {
  requirePositive("makeCylinder: radius", radius, "m");
  requirePositive("makeCylinder: length", length, "m");
  requireSegments("makeCylinder: segments", segments, 3);
  requireSegments("makeCylinder: rings", rings, 1);
  std::vector<Eigen::Vector3d> vertices;
  for (int j = 0; j <= rings; ++j) {
    const double z = -0.5 * length + length * j / rings;
    for (int i = 0; i < segments; ++i) {
      const double u = 2.0 * M_PI * i / segments;
      vertices.emplace_back(radius * std::cos(u), radius * std::sin(u), z);
    }
  }
  std::vector<Eigen::Vector3i> triangles;
  addWrappedGrid(segments, rings + 1, false, triangles);
  const int bottom = static_cast<int>(vertices.size());
  vertices.emplace_back(0.0, 0.0, -0.5 * length);
  vertices.emplace_back(0.0, 0.0, 0.5 * length);
  const int top_ring = segments * rings;
  for (int i = 0; i < segments; ++i) {
    const int i1 = (i + 1) % segments;
    triangles.emplace_back(bottom, i1, i);
    triangles.emplace_back(bottom + 1, top_ring + i, top_ring + i1);
  }
  return toMesh(vertices, triangles);
}

TriMesh makeTorus(double major, double minor, int major_segments, int minor_segments) {
  requirePositive("makeTorus: minor", minor, "m");
  if (!std::isfinite(major) || !(major > minor)) {
    throw std::invalid_argument(
        "makeTorus: major = " + std::to_string(major) +
        " m is out of range: must be finite and > minor = " + std::to_string(minor) + " m");
  }
  requireSegments("makeTorus: major_segments", major_segments, 3);
  requireSegments("makeTorus: minor_segments", minor_segments, 3);
  std::vector<Eigen::Vector3d> vertices;
  for (int j = 0; j < minor_segments; ++j) {
    const double v = 2.0 * M_PI * j / minor_segments;
    for (int i = 0; i < major_segments; ++i) {
      const double u = 2.0 * M_PI * i / major_segments;
      const double rho = major + minor * std::cos(v);
      vertices.emplace_back(rho * std::cos(u), rho * std::sin(u), minor * std::sin(v));
    }
  }
  std::vector<Eigen::Vector3i> triangles;
  addWrappedGrid(major_segments, minor_segments, true, triangles);
  return toMesh(vertices, triangles);
}

}  // namespace surgical_sim::core
