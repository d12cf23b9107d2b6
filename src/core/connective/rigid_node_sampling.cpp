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

/// Gauss-Legendre points on [-1, 1] and weights (summing to 2), n in [1, 3].
void gaussLegendre(int n, std::vector<double>& points, std::vector<double>& weights) {
  if (n == 1) {
    points = {0.0};
    weights = {2.0};
  } else if (n == 2) {
    points = {-1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0)};
    weights = {1.0, 1.0};
  } else {
    points = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
    weights = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  }
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
                                    const Eigen::Vector3i& nodes, int gauss_points,
                                    const Material& material,
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
  if (gauss_points < 1 || gauss_points > 3) {
    std::ostringstream msg;
    msg << "trilinearGridLayout: gauss_points = " << gauss_points << " must be in [1, 3]";
    throw std::invalid_argument(msg.str());
  }
  requireNonNegative("trilinearGridLayout: volume", volume, "m^3");
  std::vector<double> gp, gw;
  gaussLegendre(gauss_points, gp, gw);
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
        for (int c = 0; c < gauss_points; ++c) {
          for (int b = 0; b < gauss_points; ++b) {
            for (int a = 0; a < gauss_points; ++a) {
              const Eigen::Vector3d t(gp[a], gp[b], gp[c]);
              const Eigen::Vector3d p =
                  cell_min + 0.5 * cell.cwiseProduct(t + Eigen::Vector3d::Ones());
              if (inside && !inside(p)) continue;
              const double v = cell.prod() * gw[a] * gw[b] * gw[c] / 8.0;
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
