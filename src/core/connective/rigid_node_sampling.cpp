#include "surgical_sim/core/connective/rigid_node_sampling.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/mesh/surface_closure.h"

namespace surgical_sim::core {
namespace {

RigidNodeSample sampleOf(const Material& material, const Eigen::Vector3d& p, double volume,
                         SampleWeights weights) {
  RigidNodeSample sample;
  sample.rest_position = p;
  sample.volume = volume;
  sample.lambda = material.lambda();
  sample.mu = material.mu();
  sample.density = material.density;
  sample.weights = std::move(weights);
  return sample;
}

/// The 3-point Gauss-Legendre rule on [-1, 1] (weights sum to 2).
constexpr double kGaussPoints[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
constexpr double kGaussWeights[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};

/// layout.rest = the nodes of `positions` some sample uses (in order, identity orientation);
/// sample node indices renumbered accordingly.
void keepUsedNodes(const std::vector<Eigen::Vector3d>& positions, RigidNodeLayout& layout) {
  std::vector<int> renumber(positions.size(), -1);
  for (const RigidNodeSample& s : layout.samples)
    for (int n : s.weights.nodes) renumber[n] = 0;
  layout.rest = RigidNodeConfiguration();
  for (size_t i = 0; i < positions.size(); ++i) {
    if (renumber[i] < 0) continue;
    renumber[i] = layout.rest.numNodes();
    layout.rest.p_TN.push_back(positions[i]);
    layout.rest.q_TN.push_back(Eigen::Quaterniond::Identity());
  }
  for (RigidNodeSample& s : layout.samples)
    for (int& n : s.weights.nodes) n = renumber[n];
}

/// Generalized winding number of a closed surface at p: 1 inside, 0 outside (solid angles of
/// the triangles, Van Oosterom and Strackee).
double windingNumber(const TriMesh& surface, const Eigen::Vector3d& p) {
  double total = 0.0;
  for (int t = 0; t < surface.triangles.cols(); ++t) {
    const Eigen::Vector3d a = surface.vertices.col(surface.triangles(0, t)) - p;
    const Eigen::Vector3d b = surface.vertices.col(surface.triangles(1, t)) - p;
    const Eigen::Vector3d c = surface.vertices.col(surface.triangles(2, t)) - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2.0 * std::atan2(numerator, denominator);
  }
  return total / (4.0 * M_PI);
}

/// Dart throwing: points of the box [lo, hi] inside the surface, pairwise >= spacing apart.
std::vector<Eigen::Vector3d> poissonDisk(const TriMesh& surface, const Eigen::Vector3d& lo,
                                         const Eigen::Vector3d& hi, double spacing,
                                         std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int rejected = 0; rejected < 30 * static_cast<int>(points.size()) + 1000;) {
    const Eigen::Vector3d p =
        lo + (hi - lo).cwiseProduct(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    bool keep = windingNumber(surface, p) > 0.5;
    for (size_t i = 0; keep && i < points.size(); ++i)
      keep = (points[i] - p).squaredNorm() >= spacing * spacing;
    if (keep) {
      points.push_back(p);
      rejected = 0;
    } else {
      ++rejected;
    }
  }
  return points;
}

}  // namespace

RigidNodeLayout tetMeshLayout(const TetMesh& mesh, const Material& material) {
  const Material m = Material::validated(material);
  if (mesh.type != ElementType::Tet4 || mesh.numElements() == 0) {
    std::ostringstream msg;
    msg << "tetMeshLayout: mesh of " << mesh.numElements() << " " << toString(mesh.type)
        << " elements: needs at least one Tet4 element";
    throw std::invalid_argument(msg.str());
  }
  RigidNodeLayout layout;
  for (int i = 0; i < mesh.numNodes(); ++i) {
    layout.rest.p_TN.push_back(mesh.nodes.col(i));
    layout.rest.q_TN.push_back(Eigen::Quaterniond::Identity());
  }
  const double a = 0.5854101966249685, b = 0.1381966011250105;
  for (int e = 0; e < mesh.numElements(); ++e) {
    std::array<int, 4> nodes;
    std::array<Eigen::Vector3d, 4> corners;
    for (int c = 0; c < 4; ++c) {
      nodes[c] = mesh.elements(c, e);
      corners[c] = mesh.nodes.col(nodes[c]);
    }
    const double volume =
        std::abs((corners[1] - corners[0])
                     .dot((corners[2] - corners[0]).cross(corners[3] - corners[0]))) /
        6.0;
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      for (int c = 0; c < 4; ++c) p += (c == k ? a : b) * corners[c];
      layout.samples.push_back(
          sampleOf(m, p, 0.25 * volume, tetBarycentricWeights(nodes, corners, p)));
    }
  }
  return layout;
}

RigidNodeLayout trilinearGridLayout(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& size,
                                    const Eigen::Vector3i& nodes, const Material& material,
                                    const std::function<bool(const Eigen::Vector3d&)>& inside,
                                    double volume) {
  const Material m = Material::validated(material);
  for (int k = 0; k < 3; ++k) {
    requireFinite("trilinearGridLayout: min_corner[" + std::to_string(k) + "]", min_corner[k], "m");
    requirePositive("trilinearGridLayout: size[" + std::to_string(k) + "]", size[k], "m");
    if (nodes[k] < 2) {
      std::ostringstream msg;
      msg << "trilinearGridLayout: nodes[" << k << "] = " << nodes[k] << " must be >= 2";
      throw std::invalid_argument(msg.str());
    }
  }
  requireNonNegative("trilinearGridLayout: volume", volume, "m^3");
  const Eigen::Vector3d cell = size.cwiseQuotient((nodes - Eigen::Vector3i::Ones()).cast<double>());
  auto gridIndex = [&](int i, int j, int k) { return i + nodes.x() * (j + nodes.y() * k); };

  std::vector<RigidNodeSample> samples;
  for (int k = 0; k + 1 < nodes.z(); ++k) {
    for (int j = 0; j + 1 < nodes.y(); ++j) {
      for (int i = 0; i + 1 < nodes.x(); ++i) {
        const Eigen::Vector3d cell_min = min_corner + cell.cwiseProduct(Eigen::Vector3d(i, j, k));
        std::array<int, 8> corner_nodes;
        for (int c = 0; c < 8; ++c)
          corner_nodes[c] = gridIndex(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        for (int c = 0; c < 3; ++c) {
          for (int b = 0; b < 3; ++b) {
            for (int a = 0; a < 3; ++a) {
              const Eigen::Vector3d t(kGaussPoints[a], kGaussPoints[b], kGaussPoints[c]);
              const Eigen::Vector3d p =
                  cell_min + 0.5 * cell.cwiseProduct(t + Eigen::Vector3d::Ones());
              if (inside && !inside(p)) continue;
              const double v =
                  cell.prod() * kGaussWeights[a] * kGaussWeights[b] * kGaussWeights[c] / 8.0;
              samples.push_back(
                  sampleOf(m, p, v, trilinearWeights(corner_nodes, cell_min, cell, p)));
            }
          }
        }
      }
    }
  }
  if (samples.empty())
    throw std::invalid_argument("trilinearGridLayout: no sample lies inside the body");

  std::vector<Eigen::Vector3d> positions;
  for (int k = 0; k < nodes.z(); ++k)
    for (int j = 0; j < nodes.y(); ++j)
      for (int i = 0; i < nodes.x(); ++i)
        positions.push_back(min_corner + cell.cwiseProduct(Eigen::Vector3d(i, j, k)));
  RigidNodeLayout layout;
  layout.samples = std::move(samples);
  keepUsedNodes(positions, layout);
  double total = 0.0;
  for (const RigidNodeSample& s : layout.samples) total += s.volume;
  if (volume > 0.0)
    for (RigidNodeSample& s : layout.samples) s.volume *= volume / total;
  return layout;
}

RigidNodeLayout poissonDiskLayout(const TriMesh& surface, double node_spacing,
                                  double sample_spacing, int neighbours, const Material& material,
                                  std::mt19937& rng) {
  const Material m = Material::validated(material);
  requirePositive("poissonDiskLayout: sample_spacing", sample_spacing, "m");
  if (!(node_spacing > sample_spacing) || !std::isfinite(node_spacing)) {
    std::ostringstream msg;
    msg << "poissonDiskLayout: node_spacing = " << node_spacing
        << " m is out of range: must be finite and > sample_spacing = " << sample_spacing << " m";
    throw std::invalid_argument(msg.str());
  }
  if (surface.triangles.cols() == 0 || checkSurfaceClosure(surface.triangles).open_edges != 0)
    throw std::invalid_argument("poissonDiskLayout: the surface is not closed (open edges)");
  double volume = 0.0;
  for (int t = 0; t < surface.triangles.cols(); ++t)
    volume += surface.vertices.col(surface.triangles(0, t))
                  .dot(surface.vertices.col(surface.triangles(1, t))
                           .cross(surface.vertices.col(surface.triangles(2, t)))) /
              6.0;
  requirePositive("poissonDiskLayout: enclosed volume", volume, "m^3");
  const Eigen::Vector3d lo = surface.vertices.rowwise().minCoeff();
  const Eigen::Vector3d hi = surface.vertices.rowwise().maxCoeff();
  const std::vector<Eigen::Vector3d> nodes = poissonDisk(surface, lo, hi, node_spacing, rng);
  const std::vector<Eigen::Vector3d> points = poissonDisk(surface, lo, hi, sample_spacing, rng);
  if (neighbours < 1 || neighbours > kMaxSampleNeighbours ||
      neighbours > static_cast<int>(nodes.size())) {
    std::ostringstream msg;
    msg << "poissonDiskLayout: neighbours = " << neighbours << " is out of range: must be in [1, "
        << std::min<int>(kMaxSampleNeighbours, static_cast<int>(nodes.size())) << "] (at most "
        << nodes.size() << " rigid nodes fit at node_spacing)";
    throw std::invalid_argument(msg.str());
  }
  RigidNodeLayout layout;
  for (const Eigen::Vector3d& p : points)
    layout.samples.push_back(sampleOf(m, p, volume / static_cast<double>(points.size()),
                                      shepardWeights(nodes, p, neighbours, 2.0)));
  keepUsedNodes(nodes, layout);
  return layout;
}

}  // namespace surgical_sim::core
