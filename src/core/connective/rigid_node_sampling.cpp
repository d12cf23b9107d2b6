#include "surgical_sim/core/connective/rigid_node_sampling.h"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/common/validate.h"

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

  // Keep the nodes some sample depends on, renumbered in grid order.
  const int grid_nodes = nodes.prod();
  std::vector<int> renumber(grid_nodes, -1);
  for (const RigidNodeSample& s : samples)
    for (int n : s.weights.nodes) renumber[n] = 0;
  RigidNodeLayout layout;
  for (int k = 0; k < nodes.z(); ++k) {
    for (int j = 0; j < nodes.y(); ++j) {
      for (int i = 0; i < nodes.x(); ++i) {
        const int g = gridIndex(i, j, k);
        if (renumber[g] < 0) continue;
        renumber[g] = layout.rest.numNodes();
        layout.rest.p_TN.push_back(min_corner + cell.cwiseProduct(Eigen::Vector3d(i, j, k)));
        layout.rest.q_TN.push_back(Eigen::Quaterniond::Identity());
      }
    }
  }
  double total = 0.0;
  for (RigidNodeSample& s : samples) {
    for (int& n : s.weights.nodes) n = renumber[n];
    total += s.volume;
  }
  if (volume > 0.0)
    for (RigidNodeSample& s : samples) s.volume *= volume / total;
  layout.samples = std::move(samples);
  return layout;
}

}  // namespace surgical_sim::core
