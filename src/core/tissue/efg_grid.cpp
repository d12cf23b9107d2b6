#include "surgical_sim/core/tissue/efg_grid.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "surgical_sim/core/mesh/surface_closure.h"
#include "surgical_sim/core/mesh/surface_inside.h"

namespace surgical_sim::core {
namespace {

// Largest number of integration cells in the bounding box.
constexpr double kMaxCells = 8e6;
// Largest number of volume samples in the bounding box (one byte each).
constexpr double kMaxSamples = 5e8;
// Barycentric tolerance of the point-in-tet test [-]: samples on a face count as inside.
constexpr double kInsideTolerance = 1e-12;

using GridIndex = std::array<int, 3>;

// Marks samples[i + S_x (j + S_y k)] for every sample point (lattice of pitch d / s, offset by
// half a pitch from `origin`) inside a tet of `mesh`.
std::vector<std::uint8_t> markInsideSamples(const TetMesh& mesh, const Eigen::Vector3d& origin,
                                            double pitch, const Eigen::Vector3i& count) {
  std::vector<std::uint8_t> inside(static_cast<size_t>(count.prod()), 0);
  for (int e = 0; e < mesh.numElements(); ++e) {
    Eigen::Matrix<double, 3, 4> corners;
    for (int a = 0; a < 4; ++a) {
      const int node = mesh.elements(a, e);
      if (node < 0 || node >= mesh.numNodes()) {
        throw std::invalid_argument("EfgModel: mesh.elements(" + std::to_string(a) + ", " +
                                    std::to_string(e) + ") = " + std::to_string(node) +
                                    " is not a node index");
      }
      corners.col(a) = mesh.nodes.col(node);
    }
    Eigen::Matrix3d T;
    T << corners.col(1) - corners.col(0), corners.col(2) - corners.col(0),
        corners.col(3) - corners.col(0);
    const double det = T.determinant();
    if (!(std::abs(det) > 0.0)) continue;  // a flat tet holds no volume
    const Eigen::Matrix3d T_inv = T.inverse();
    const Eigen::Vector3d lo = corners.rowwise().minCoeff();
    const Eigen::Vector3d hi = corners.rowwise().maxCoeff();
    Eigen::Vector3i first;
    Eigen::Vector3i last;
    for (int c = 0; c < 3; ++c) {
      first(c) = std::max(0, static_cast<int>(std::ceil((lo(c) - origin(c)) / pitch - 0.5)));
      last(c) =
          std::min(count(c) - 1, static_cast<int>(std::floor((hi(c) - origin(c)) / pitch - 0.5)));
    }
    for (int k = first.z(); k <= last.z(); ++k) {
      for (int j = first.y(); j <= last.y(); ++j) {
        for (int i = first.x(); i <= last.x(); ++i) {
          const Eigen::Vector3d q = origin + pitch * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
          const Eigen::Vector3d b = T_inv * (q - corners.col(0));
          if (b.minCoeff() >= -kInsideTolerance && b.sum() <= 1.0 + kInsideTolerance) {
            inside[static_cast<size_t>(i + count.x() * (j + static_cast<int64_t>(count.y()) * k))] =
                1;
          }
        }
      }
    }
  }
  return inside;
}

// Offsets of the grid particles around a DOF cell, sorted by distance from the IP at the cell's
// lowest sub-cell (then by offset), with the 8 corners first. The IP in sub-cell (a, b, c) uses
// the mirrored offsets.
std::vector<GridIndex> neighbourOffsets() {
  std::vector<GridIndex> offsets;
  for (int k = -2; k <= 3; ++k)
    for (int j = -2; j <= 3; ++j)
      for (int i = -2; i <= 3; ++i) offsets.push_back({i, j, k});
  const auto key = [](const GridIndex& o) {
    const bool corner = o[0] >= 0 && o[0] <= 1 && o[1] >= 0 && o[1] <= 1 && o[2] >= 0 && o[2] <= 1;
    // Squared distance in units of d / 2 from the IP at (0.5, 0.5, 0.5) d of the DOF cell.
    int r2 = 0;
    for (int c = 0; c < 3; ++c) r2 += (4 * o[c] - 1) * (4 * o[c] - 1);
    return std::make_tuple(!corner, r2, o[2], o[1], o[0]);
  };
  std::sort(offsets.begin(), offsets.end(),
            [&](const GridIndex& a, const GridIndex& b) { return key(a) < key(b); });
  return offsets;
}

// Marks the volume samples inside the body: (lattice origin [m], pitch [m], count per axis) ->
// one byte per sample, as markInsideSamples.
using SampleMarker = std::function<std::vector<std::uint8_t>(const Eigen::Vector3d&, double,
                                                             const Eigen::Vector3i&)>;

// The grids over the bounding box of `body` (points [m], finite, at least one), with the inside
// samples given by `mark`.
EfgGrid buildGrid(const Eigen::Matrix3Xd& body, const EfgOptions& options,
                  const SampleMarker& mark) {
  const double d = options.spacing;
  const int s = options.volume_samples;
  EfgGrid grid;
  grid.spacing = d;
  grid.origin = body.rowwise().minCoeff();
  const Eigen::Vector3d extent = body.rowwise().maxCoeff() - grid.origin;
  // DOF cells per axis (>= 1) covering the bounding box; twice as many integration cells.
  Eigen::Vector3i dof_cells;
  double cells = 1.0;
  for (int c = 0; c < 3; ++c) {
    const double n = std::max(1.0, std::ceil(extent(c) / (2.0 * d) - 1e-9));
    cells *= 2.0 * n;
    if (cells > kMaxCells) {
      throw std::invalid_argument("EfgModel: efg.spacing = " + std::to_string(d) +
                                  " m gives more than 8e6 integration cells in the mesh's "
                                  "bounding box: increase it");
    }
    dof_cells(c) = static_cast<int>(n);
  }
  if (cells * s * s * s > kMaxSamples) {
    throw std::invalid_argument("EfgModel: efg.volume_samples = " + std::to_string(s) +
                                " gives more than 5e8 volume samples in the mesh's bounding box: "
                                "decrease it or increase efg.spacing");
  }
  const Eigen::Vector3i ip_cells = 2 * dof_cells;
  grid.cells = ip_cells;
  grid.ip_of_cell.assign(static_cast<size_t>(ip_cells.prod()), -1);
  const Eigen::Vector3i samples = s * ip_cells;
  const std::vector<std::uint8_t> inside = mark(grid.origin, d / s, samples);

  // Kept cells, then the particles at the corners of their DOF cells.
  std::vector<GridIndex> kept;
  std::vector<Eigen::Vector3d> points;
  std::vector<double> volumes;
  const double sample_volume = std::pow(d / s, 3);
  for (int k = 0; k < ip_cells.z(); ++k) {
    for (int j = 0; j < ip_cells.y(); ++j) {
      for (int i = 0; i < ip_cells.x(); ++i) {
        int count = 0;
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();  // of the inside samples' sub-cell indices
        for (int c = 0; c < s; ++c)
          for (int b = 0; b < s; ++b)
            for (int a = 0; a < s; ++a)
              if (inside[static_cast<size_t>(
                      s * i + a +
                      samples.x() *
                          (s * j + b + static_cast<int64_t>(samples.y()) * (s * k + c)))]) {
                ++count;
                sum += Eigen::Vector3d(a + 0.5, b + 0.5, c + 0.5);
              }
        if (count == 0) continue;
        grid.ip_of_cell[static_cast<size_t>(i + ip_cells.x() * (j + ip_cells.y() * k))] =
            static_cast<int>(points.size());
        kept.push_back({i, j, k});
        const Eigen::Vector3d offset = options.ip_at_centroid ? Eigen::Vector3d(sum / (count * s))
                                                              : Eigen::Vector3d::Constant(0.5);
        points.push_back(grid.origin + d * (Eigen::Vector3d(i, j, k) + offset));
        volumes.push_back(count * sample_volume);
      }
    }
  }
  const std::vector<GridIndex> offsets = neighbourOffsets();
  // Grid index of the particle at `offset` (mirrored by sub-cell) from IP cell `ip`.
  const auto particleIndex = [](const GridIndex& ip, const GridIndex& offset) {
    GridIndex g;
    for (int c = 0; c < 3; ++c) g[c] = ip[c] / 2 + (ip[c] % 2 == 0 ? offset[c] : 1 - offset[c]);
    return g;
  };
  std::map<GridIndex, int> particle_of;  // grid index -> particle
  std::vector<Eigen::Vector3d> particles;
  for (const GridIndex& ip : kept) {
    for (size_t o = 0; o < 8; ++o) {
      const GridIndex g = particleIndex(ip, offsets[o]);
      if (particle_of.emplace(g, static_cast<int>(particles.size())).second)
        particles.push_back(grid.origin + 2.0 * d * Eigen::Vector3d(g[0], g[1], g[2]));
    }
  }
  // Neighbours: the corners, then the nearest other existing particles.
  std::vector<int> neighbours;
  for (const GridIndex& ip : kept) {
    int found = 0;
    for (size_t o = 0; o < offsets.size() && found < options.neighbours; ++o) {
      const auto it = particle_of.find(particleIndex(ip, offsets[o]));
      if (it == particle_of.end()) continue;
      neighbours.push_back(it->second);
      ++found;
    }
    if (found < options.neighbours) {
      throw std::invalid_argument(
          "EfgModel: efg.neighbours = " + std::to_string(options.neighbours) + ": only " +
          std::to_string(found) +
          " particles lie near the integration "
          "point of cell (" +
          std::to_string(ip[0]) + ", " + std::to_string(ip[1]) + ", " + std::to_string(ip[2]) +
          ")");
    }
  }
  if (points.empty()) {
    throw std::invalid_argument("EfgModel: no integration cell of efg.spacing = " +
                                std::to_string(d) + " m has a volume sample inside the mesh");
  }
  const auto m = static_cast<Eigen::Index>(points.size());
  grid.particles.resize(3, static_cast<Eigen::Index>(particles.size()));
  for (size_t p = 0; p < particles.size(); ++p)
    grid.particles.col(static_cast<Eigen::Index>(p)) = particles[p];
  grid.integration_points.resize(3, m);
  for (Eigen::Index e = 0; e < m; ++e)
    grid.integration_points.col(e) = points[static_cast<size_t>(e)];
  grid.volumes = Eigen::Map<const Eigen::VectorXd>(volumes.data(), m);
  grid.neighbours = Eigen::Map<const Eigen::MatrixXi>(neighbours.data(), options.neighbours, m);
  return grid;
}

}  // namespace

EfgGrid buildEfgGrid(const TetMesh& mesh, const EfgOptions& options) {
  options.validate();
  if (mesh.numNodes() == 0 || mesh.numElements() == 0) {
    throw std::invalid_argument("EfgModel: mesh has no nodes or no elements");
  }
  if (!mesh.nodes.allFinite()) throw std::invalid_argument("EfgModel: mesh.nodes not finite");
  return buildGrid(
      mesh.nodes, options,
      [&mesh](const Eigen::Vector3d& origin, double pitch, const Eigen::Vector3i& count) {
        return markInsideSamples(mesh, origin, pitch, count);
      });
}

EfgGrid buildEfgGrid(const TriMesh& surface, const EfgOptions& options) {
  options.validate();
  if (surface.vertices.cols() == 0 || surface.triangles.cols() == 0) {
    throw std::invalid_argument("EfgModel: surface has no vertices or no triangles");
  }
  if (!surface.vertices.allFinite())
    throw std::invalid_argument("EfgModel: surface.vertices not finite");
  const SurfaceClosure closure = checkSurfaceClosure(surface.triangles);
  if (closure.open_edges > 0) {
    throw std::invalid_argument("EfgModel: the surface is not closed (" +
                                std::to_string(closure.open_edges) +
                                " open or inconsistently oriented edges): its inside is undefined");
  }
  return buildGrid(
      surface.vertices, options,
      [&surface](const Eigen::Vector3d& origin, double pitch, const Eigen::Vector3i& count) {
        return markInsideLattice(surface, origin, pitch, count);
      });
}

}  // namespace surgical_sim::core
