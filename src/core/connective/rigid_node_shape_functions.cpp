#include "surgical_sim/core/connective/rigid_node_shape_functions.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {
namespace {

[[noreturn]] void fail(const std::string& message) { throw std::invalid_argument(message); }

void requireFinitePoint(const char* name, const Eigen::Vector3d& p) {
  if (!p.allFinite()) {
    std::ostringstream msg;
    msg << name << " (" << p.transpose() << ") m is not finite";
    fail(msg.str());
  }
}

}  // namespace

SampleWeights tetBarycentricWeights(const std::array<int, 4>& nodes,
                                    const std::array<Eigen::Vector3d, 4>& corners,
                                    const Eigen::Vector3d& p) {
  for (const Eigen::Vector3d& c : corners) requireFinitePoint("tetBarycentricWeights: corner", c);
  requireFinitePoint("tetBarycentricWeights: point", p);
  Eigen::Matrix3d D;
  for (int k = 0; k < 3; ++k) D.col(k) = corners[k + 1] - corners[0];
  double longest = 0.0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) longest = std::max(longest, (corners[a] - corners[b]).norm());
  const double det = D.determinant();
  if (!(std::abs(det) > 1e-12 * longest * longest * longest)) {
    std::ostringstream msg;
    msg << "tetBarycentricWeights: tet of rigid nodes " << nodes[0] << ", " << nodes[1] << ", "
        << nodes[2] << ", " << nodes[3] << " is degenerate (det = " << det << " m^3, longest edge "
        << longest << " m): must be > 1e-12 longest edge^3";
    fail(msg.str());
  }
  const Eigen::Matrix3d Dinv = D.inverse();
  const Eigen::Vector3d bary = Dinv * (p - corners[0]);
  SampleWeights w;
  w.nodes.assign(nodes.begin(), nodes.end());
  w.weights = {1.0 - bary.sum(), bary.x(), bary.y(), bary.z()};
  w.gradients.resize(4);
  for (int k = 0; k < 3; ++k) w.gradients[k + 1] = Dinv.row(k).transpose();
  w.gradients[0] = -(w.gradients[1] + w.gradients[2] + w.gradients[3]);
  return w;
}

SampleWeights trilinearWeights(const std::array<int, 8>& nodes, const Eigen::Vector3d& cell_min,
                               const Eigen::Vector3d& cell_size, const Eigen::Vector3d& p) {
  requireFinitePoint("trilinearWeights: cell_min", cell_min);
  requireFinitePoint("trilinearWeights: point", p);
  for (int k = 0; k < 3; ++k)
    requirePositive("trilinearWeights: cell_size[" + std::to_string(k) + "]", cell_size[k], "m");
  const Eigen::Vector3d t = (p - cell_min).cwiseQuotient(cell_size);
  SampleWeights w;
  w.nodes.assign(nodes.begin(), nodes.end());
  w.weights.resize(8);
  w.gradients.resize(8);
  for (int c = 0; c < 8; ++c) {
    Eigen::Vector3d factor, slope;
    for (int k = 0; k < 3; ++k) {
      const bool upper = (c >> k) & 1;
      factor[k] = upper ? t[k] : 1.0 - t[k];
      slope[k] = (upper ? 1.0 : -1.0) / cell_size[k];
    }
    w.weights[c] = factor.prod();
    w.gradients[c] =
        Eigen::Vector3d(slope.x() * factor.y() * factor.z(), factor.x() * slope.y() * factor.z(),
                        factor.x() * factor.y() * slope.z());
  }
  return w;
}

SampleWeights shepardWeights(const std::vector<Eigen::Vector3d>& node_positions,
                             const Eigen::Vector3d& p, int neighbours, double exponent) {
  const int n = static_cast<int>(node_positions.size());
  if (neighbours < 1 || neighbours > n) {
    std::ostringstream msg;
    msg << "shepardWeights: neighbours = " << neighbours << " is out of range: must be in [1, " << n
        << "] (the number of rigid nodes)";
    fail(msg.str());
  }
  requirePositive("shepardWeights: exponent", exponent, "");
  requireFinitePoint("shepardWeights: point", p);
  for (const Eigen::Vector3d& x : node_positions)
    requireFinitePoint("shepardWeights: rigid node position", x);
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  auto closer = [&](int a, int b) {
    const double da = (node_positions[a] - p).squaredNorm();
    const double db = (node_positions[b] - p).squaredNorm();
    return da < db || (da == db && a < b);
  };
  std::partial_sort(order.begin(), order.begin() + neighbours, order.end(), closer);
  const double farthest = (node_positions[order[neighbours - 1]] - p).norm();
  const double nearest = (node_positions[order[0]] - p).norm();
  if (!(nearest > 1e-9 * farthest) || nearest == 0.0) {
    std::ostringstream msg;
    msg << "shepardWeights: point (" << p.transpose() << ") m coincides with rigid node "
        << order[0] << " (distance " << nearest
        << " m): Shepard weights are singular at a node; move the sample off the node";
    fail(msg.str());
  }
  SampleWeights w;
  w.nodes.assign(order.begin(), order.begin() + neighbours);
  w.weights.resize(neighbours);
  w.gradients.resize(neighbours);
  double phi_sum = 0.0;
  Eigen::Vector3d grad_sum = Eigen::Vector3d::Zero();
  for (int k = 0; k < neighbours; ++k) {
    // Distances relative to the nearest one keep phi in range for any length unit.
    const Eigen::Vector3d r = p - node_positions[w.nodes[k]];
    const double d = r.norm();
    const double phi = std::pow(d / nearest, -exponent);
    w.weights[k] = phi;
    w.gradients[k] = -exponent * phi / (d * d) * r;
    phi_sum += phi;
    grad_sum += w.gradients[k];
  }
  for (int k = 0; k < neighbours; ++k) {
    w.weights[k] /= phi_sum;
    w.gradients[k] = (w.gradients[k] - w.weights[k] * grad_sum) / phi_sum;
  }
  return w;
}

void checkSampleWeights(const SampleWeights& w, int num_nodes, const std::string& what) {
  const size_t k = w.nodes.size();
  if (k == 0 || w.weights.size() != k || w.gradients.size() != k) {
    std::ostringstream msg;
    msg << what << ": " << k << " nodes, " << w.weights.size() << " weights and "
        << w.gradients.size() << " gradients: need at least one node and equal lengths";
    fail(msg.str());
  }
  double sum = 0.0, gradient_scale = 0.0;
  Eigen::Vector3d gradient_sum = Eigen::Vector3d::Zero();
  for (size_t a = 0; a < k; ++a) {
    if (w.nodes[a] < 0 || w.nodes[a] >= num_nodes) {
      std::ostringstream msg;
      msg << what << ": rigid node index " << w.nodes[a] << " is out of range: must be in [0, "
          << num_nodes << ")";
      fail(msg.str());
    }
    for (size_t b = 0; b < a; ++b) {
      if (w.nodes[a] == w.nodes[b]) {
        std::ostringstream msg;
        msg << what << ": rigid node " << w.nodes[a] << " is listed twice";
        fail(msg.str());
      }
    }
    if (!std::isfinite(w.weights[a]) || !w.gradients[a].allFinite()) {
      std::ostringstream msg;
      msg << what << ": weight or gradient of rigid node " << w.nodes[a] << " is not finite";
      fail(msg.str());
    }
    sum += w.weights[a];
    gradient_sum += w.gradients[a];
    gradient_scale += w.gradients[a].norm();
  }
  if (!(std::abs(sum - 1.0) <= 1e-9)) {
    std::ostringstream msg;
    msg << what << ": weights sum to " << sum << ": must be 1 within 1e-9 (a partition of unity)";
    fail(msg.str());
  }
  if (!(gradient_sum.norm() <= 1e-9 * gradient_scale)) {
    std::ostringstream msg;
    msg << what << ": weight gradients sum to (" << gradient_sum.transpose()
        << ") 1/m: must be 0 within 1e-9 of sum |grad w| = " << gradient_scale;
    fail(msg.str());
  }
}

}  // namespace surgical_sim::core
