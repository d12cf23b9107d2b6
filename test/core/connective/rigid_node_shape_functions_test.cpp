#include "surgical_sim/core/connective/rigid_node_shape_functions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "rigid_node_test_util.h"

namespace surgical_sim::core {
namespace {

using test::randomVector;

/// sum w = 1, sum grad w = 0, grad w equal to central differences of w, and (if linear) the
/// weights reproduce the point from the node positions.
void expectPartitionOfUnity(const std::function<SampleWeights(const Eigen::Vector3d&)>& weights,
                            const std::vector<Eigen::Vector3d>& node_positions,
                            const Eigen::Vector3d& p, bool linear, double length) {
  const SampleWeights w = weights(p);
  double sum = 0.0;
  Eigen::Vector3d gradient_sum = Eigen::Vector3d::Zero(), reproduced = Eigen::Vector3d::Zero();
  double gradient_scale = 0.0;
  for (size_t a = 0; a < w.nodes.size(); ++a) {
    sum += w.weights[a];
    gradient_sum += w.gradients[a];
    gradient_scale += w.gradients[a].norm();
    reproduced += w.weights[a] * node_positions[w.nodes[a]];
  }
  EXPECT_NEAR(sum, 1.0, 1e-13);
  EXPECT_LE(gradient_sum.norm(), 1e-12 * gradient_scale);
  if (linear) {
    EXPECT_LE((reproduced - p).norm(), 1e-12 * length);
  }
  const double h = 1e-6 * length;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(k);
    const SampleWeights plus = weights(p + e), minus = weights(p - e);
    for (size_t a = 0; a < w.nodes.size(); ++a) {
      ASSERT_EQ(plus.nodes[a], w.nodes[a]);
      const double fd = (plus.weights[a] - minus.weights[a]) / (2.0 * h);
      EXPECT_NEAR(w.gradients[a][k], fd, 1e-6 * gradient_scale) << "node " << a << " axis " << k;
    }
  }
  EXPECT_NO_THROW(checkSampleWeights(w, static_cast<int>(node_positions.size()), "w"));
}

TEST(RigidNodeShapeFunctions, TetBarycentricIsAPartitionOfUnityReproducingLinearFields) {
  std::mt19937 rng(3);
  const std::vector<Eigen::Vector3d> corners = {
      Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.2, 0.1, 0), Eigen::Vector3d(0.2, 0.9, 0.1),
      Eigen::Vector3d(0.3, 0.2, 1.1)};
  const std::array<int, 4> nodes = {0, 1, 2, 3};
  const std::array<Eigen::Vector3d, 4> c = {corners[0], corners[1], corners[2], corners[3]};
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Vector3d p = Eigen::Vector3d::Constant(0.3) + randomVector(rng, 0.1);
    expectPartitionOfUnity(
        [&](const Eigen::Vector3d& x) { return tetBarycentricWeights(nodes, c, x); }, corners, p,
        true, 1.0);
  }
  // The weights are the barycentric coordinates: 1 at its corner, 0 at the others.
  const SampleWeights at_corner = tetBarycentricWeights(nodes, c, corners[2]);
  for (int a = 0; a < 4; ++a) EXPECT_NEAR(at_corner.weights[a], a == 2 ? 1.0 : 0.0, 1e-14);
}

TEST(RigidNodeShapeFunctions, TrilinearIsAPartitionOfUnityReproducingLinearFields) {
  std::mt19937 rng(5);
  const Eigen::Vector3d cell_min(1.0, -2.0, 0.5), cell_size(0.5, 0.25, 2.0);
  std::array<int, 8> nodes;
  std::vector<Eigen::Vector3d> corners;
  for (int c = 0; c < 8; ++c) {
    nodes[c] = 7 - c;  // any numbering
    corners.push_back(Eigen::Vector3d::Zero());
  }
  for (int c = 0; c < 8; ++c)
    corners[nodes[c]] =
        cell_min + cell_size.cwiseProduct(Eigen::Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1));
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Vector3d t = randomVector(rng, 0.5) + Eigen::Vector3d::Constant(0.5);
    const Eigen::Vector3d p = cell_min + cell_size.cwiseProduct(t);
    expectPartitionOfUnity(
        [&](const Eigen::Vector3d& x) { return trilinearWeights(nodes, cell_min, cell_size, x); },
        corners, p, true, 1.0);
  }
}

TEST(RigidNodeShapeFunctions, ShepardIsAPartitionOfUnityInGeneralCollinearAndCoplanarLayouts) {
  std::mt19937 rng(11);
  std::vector<Eigen::Vector3d> general, collinear, coplanar;
  for (int i = 0; i < 10; ++i) {
    general.push_back(randomVector(rng, 1.0));
    collinear.push_back(Eigen::Vector3d(0.3 * i, 0.0, 0.0));
    coplanar.push_back(Eigen::Vector3d(0.4 * (i % 4), 0.5 * (i / 4), 0.0));
  }
  for (const auto* nodes : {&general, &collinear, &coplanar}) {
    for (int neighbours : {1, 4, 10}) {
      for (int trial = 0; trial < 3; ++trial) {
        // Points on the line / in the plane as well as off them.
        const Eigen::Vector3d p = (*nodes)[trial + 2] + randomVector(rng, 0.1) +
                                  (trial == 0 ? Eigen::Vector3d::Zero() : randomVector(rng, 0.05));
        expectPartitionOfUnity(
            [&](const Eigen::Vector3d& x) { return shepardWeights(*nodes, x, neighbours, 2.0); },
            *nodes, p, false, 1.0);
      }
    }
  }
}

TEST(RigidNodeShapeFunctions, BadInputIsRejectedWithTheProblemNamed) {
  const auto& throwsWith = test::expectInvalidArgument;
  const std::array<int, 4> nodes = {0, 1, 2, 3};
  const std::array<Eigen::Vector3d, 4> flat = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                               Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 1, 0)};
  throwsWith([&] { tetBarycentricWeights(nodes, flat, Eigen::Vector3d::Zero()); }, "degenerate");
  const std::vector<Eigen::Vector3d> line = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)};
  throwsWith([&] { shepardWeights(line, Eigen::Vector3d(1, 0, 0), 2, 2.0); }, "coincides");
  throwsWith([&] { shepardWeights(line, Eigen::Vector3d(0.5, 0, 0), 3, 2.0); }, "neighbours = 3");
  throwsWith([&] { shepardWeights(line, Eigen::Vector3d(0.5, 0, 0), 2, 0.0); }, "exponent");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  throwsWith([&] { shepardWeights(line, Eigen::Vector3d(nan, 0, 0), 2, 2.0); }, "not finite");
  throwsWith(
      [&] {
        trilinearWeights({0, 1, 2, 3, 4, 5, 6, 7}, Eigen::Vector3d::Zero(),
                         Eigen::Vector3d(1, 0, 1), Eigen::Vector3d::Zero());
      },
      "cell_size[1]");

  SampleWeights w = shepardWeights(line, Eigen::Vector3d(0.25, 0.1, 0), 2, 2.0);
  SampleWeights bad = w;
  bad.weights[0] += 0.01;
  throwsWith([&] { checkSampleWeights(bad, 2, "sample 4 weights"); },
             "sample 4 weights: weights sum to 1.01");
  bad = w;
  bad.gradients[0].x() += 0.5;
  throwsWith([&] { checkSampleWeights(bad, 2, "w"); }, "gradients sum");
  bad = w;
  bad.weights[1] = nan;
  throwsWith([&] { checkSampleWeights(bad, 2, "w"); }, "not finite");
  throwsWith([&] { checkSampleWeights(w, 1, "w"); }, "out of range");
  bad = w;
  bad.nodes[1] = bad.nodes[0];
  throwsWith([&] { checkSampleWeights(bad, 2, "w"); }, "listed twice");
}

}  // namespace
}  // namespace surgical_sim::core
