#include "surgical_sim/core/cutting/blade_edge_detection.h"

#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <set>

#include "surgical_sim/core/cutting/edge_sweep_ccd.h"
#include "surgical_sim/core/cutting/fragment_volume.h"
#include "surgical_sim/core/mesh/generators.h"

namespace surgical_sim::core {
namespace {

/// Unique edges (lower node, higher node) of a Tet4 mesh.
std::vector<std::array<int, 2>> meshEdges(const TetMesh& mesh) {
  std::set<std::array<int, 2>> unique;
  for (int e = 0; e < mesh.numElements(); ++e)
    for (const auto& [i, j] : kTetLocalEdges) {
      const int a = mesh.elements(i, e), b = mesh.elements(j, e);
      unique.insert({std::min(a, b), std::max(a, b)});
    }
  return {unique.begin(), unique.end()};
}

/// Blade along y (y in [-1, 2]) in the plane x = x_blade, moving down from z_from to z_to.
BladeSweep planeSweep(double x_blade, double z_from, double z_to) {
  BladeSweep sweep{Eigen::Matrix3Xd(3, 2), Eigen::Matrix3Xd(3, 2)};
  sweep.start << x_blade, x_blade, -1.0, 2.0, z_from, z_from;
  sweep.end = sweep.start;
  sweep.end.row(2).setConstant(z_to);
  return sweep;
}

std::set<int> crossedEdges(const std::vector<BladeEdgeCrossing>& crossings) {
  std::set<int> ids;
  for (const BladeEdgeCrossing& c : crossings) ids.insert(c.edge);
  return ids;
}

class BladeEdgeDetectionTest : public ::testing::Test {
 protected:
  // Unit cube, 4 x 3 x 3 cells: nodes at x = k / 4, y and z = k / 3 (none on x = 0.37).
  const TetMesh mesh = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
                               Eigen::Vector3i(4, 3, 3), ElementType::Tet4);
  const std::vector<std::array<int, 2>> edges = meshEdges(mesh);
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(mesh.nodes.data(), mesh.nodes.size());
  std::vector<std::uint8_t> none = std::vector<std::uint8_t>(edges.size(), 0);
  std::vector<std::uint8_t> outcode;
  const double x_blade = 0.37, tolerance = 1e-9;

  /// Point of edge id on the plane x = x_blade, or nothing if both nodes are on one side.
  std::optional<Eigen::Vector3d> planeCrossing(int id) const {
    const Eigen::Vector3d a = mesh.nodes.col(edges[id][0]), b = mesh.nodes.col(edges[id][1]);
    if ((a.x() < x_blade) == (b.x() < x_blade)) return std::nullopt;
    return a + (x_blade - a.x()) / (b.x() - a.x()) * (b - a);
  }
};

TEST_F(BladeEdgeDetectionTest, ThroughCutFindsExactlyTheEdgesAcrossThePlane) {
  const auto crossings = detectBladeEdgeCrossings(planeSweep(x_blade, 2.0, -1.0), x, x, edges, none,
                                                  tolerance, outcode);
  std::set<int> expected;
  for (int id = 0; id < static_cast<int>(edges.size()); ++id)
    if (planeCrossing(id)) expected.insert(id);
  EXPECT_GT(expected.size(), 0u);
  EXPECT_EQ(crossedEdges(crossings), expected);
  for (const BladeEdgeCrossing& c : crossings) {  // s locates the crossing on the edge
    const Eigen::Vector3d a = mesh.nodes.col(edges[c.edge][0]),
                          b = mesh.nodes.col(edges[c.edge][1]);
    EXPECT_NEAR(((1.0 - c.s) * a + c.s * b).x(), x_blade, 1e-9);
  }
}

TEST_F(BladeEdgeDetectionTest, BladeStoppingInsideFindsOnlyTheEdgesItsSweepReaches) {
  const double z_stop = 0.6;
  const auto crossings = detectBladeEdgeCrossings(planeSweep(x_blade, 2.0, z_stop), x, x, edges,
                                                  none, tolerance, outcode);
  std::set<int> expected;
  for (int id = 0; id < static_cast<int>(edges.size()); ++id) {
    const auto p = planeCrossing(id);
    if (p && p->z() > z_stop) expected.insert(id);
  }
  EXPECT_GT(expected.size(), 0u);
  EXPECT_EQ(crossedEdges(crossings), expected);
}

TEST_F(BladeEdgeDetectionTest, SkippedEdgesAndABladeAwayFromTheTissueFindNothing) {
  EXPECT_TRUE(
      detectBladeEdgeCrossings(planeSweep(x_blade, 5.0, 3.0), x, x, edges, none, tolerance, outcode)
          .empty());
  const std::vector<std::uint8_t> all(edges.size(), 1);
  EXPECT_TRUE(
      detectBladeEdgeCrossings(planeSweep(x_blade, 2.0, -1.0), x, x, edges, all, tolerance, outcode)
          .empty());
  std::vector<std::array<int, 2>> unrepresented(edges.size(), {-1, -1});
  EXPECT_TRUE(detectBladeEdgeCrossings(planeSweep(x_blade, 2.0, -1.0), x, x, unrepresented, none,
                                       tolerance, outcode)
                  .empty());
}

TEST_F(BladeEdgeDetectionTest, SweptBoxRejectionMissesNoCrossingOfMovingTissue) {
  // Random tissue motion and blades: the result equals testing every edge with
  // edgeSweepCrossing() and keeping the earliest crossing.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int found = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd x_end =
        x + 0.1 * Eigen::VectorXd::NullaryExpr(x.size(), [&] { return u(rng); });
    BladeSweep sweep{Eigen::Matrix3Xd(3, 3), Eigen::Matrix3Xd(3, 3)};
    for (int k = 0; k < 3; ++k) {
      sweep.start.col(k) = Eigen::Vector3d(0.5 + 0.6 * u(rng), 0.5 + 0.6 * u(rng), 1.2);
      sweep.end.col(k) = sweep.start.col(k) + Eigen::Vector3d(0.2 * u(rng), 0.2 * u(rng), -0.8);
    }
    const auto crossings =
        detectBladeEdgeCrossings(sweep, x, x_end, edges, none, tolerance, outcode);
    std::vector<BladeEdgeCrossing> brute;
    for (int id = 0; id < static_cast<int>(edges.size()); ++id) {
      const auto [a, b] = edges[id];
      std::optional<EdgeSweepHit> best;
      for (int k = 0; k + 1 < 3; ++k) {
        const auto hit =
            edgeSweepCrossing(sweep.start.col(k), sweep.start.col(k + 1), sweep.end.col(k),
                              sweep.end.col(k + 1), x.segment<3>(3 * a), x.segment<3>(3 * b),
                              x_end.segment<3>(3 * a), x_end.segment<3>(3 * b), tolerance);
        if (hit && (!best || hit->t < best->t)) best = hit;
      }
      if (best) brute.push_back({id, best->s});
    }
    ASSERT_EQ(crossings.size(), brute.size()) << "trial " << trial;
    for (std::size_t i = 0; i < brute.size(); ++i) {
      EXPECT_EQ(crossings[i].edge, brute[i].edge) << "trial " << trial;
      EXPECT_EQ(crossings[i].s, brute[i].s) << "trial " << trial;
    }
    found += static_cast<int>(brute.size());
  }
  EXPECT_GT(found, 0);
}

}  // namespace
}  // namespace surgical_sim::core
