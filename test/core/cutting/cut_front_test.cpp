#include "surgical_sim/core/cutting/cut_front.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <map>
#include <utility>

namespace surgical_sim::core {
namespace {

using V = Eigen::Vector3d;

/// Directed edge uses of a triangle list.
std::map<std::pair<int, int>, int> directedEdges(const std::vector<std::array<int, 3>>& tris) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k)
      ++uses[{t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)]}];
  return uses;
}

TEST(CutFront, StripBetweenTwoChainsIsADiskBoundedByTheChainsAndTheEndRungs) {
  // behind: 0..4 along x at y = 0; ahead: 5..7 along x at y = 1 (on the left, normal +z).
  std::vector<V> X = {V(0, 0, 0), V(1, 0, 0), V(2, 0, 0), V(3, 0, 0),
                      V(4, 0, 0), V(0, 1, 0), V(2, 1, 0), V(4, 1, 0)};
  std::vector<std::array<int, 3>> tris;
  appendStrip(
      {0, 1, 2, 3, 4}, {5, 6, 7}, [&](int v) { return X[static_cast<std::size_t>(v)]; }, tris);
  ASSERT_EQ(tris.size(), 5u + 3u - 2u);
  double area = 0.0;
  for (const auto& t : tris) {
    const V n = (X[static_cast<std::size_t>(t[1])] - X[static_cast<std::size_t>(t[0])])
                    .cross(X[static_cast<std::size_t>(t[2])] - X[static_cast<std::size_t>(t[0])]);
    EXPECT_GT(n.z(), 0.0);  // counter-clockwise about +z
    area += 0.5 * n.z();
  }
  EXPECT_NEAR(area, 4.0, 1e-12);  // the rectangle between the chains
  // Interior edges are used once in each direction; boundary edges once.
  const auto uses = directedEdges(tris);
  int boundary = 0;
  for (const auto& [e, n] : uses) {
    EXPECT_EQ(n, 1);
    if (!uses.count({e.second, e.first})) ++boundary;
  }
  EXPECT_EQ(boundary, 4 + 2 + 2);  // behind, ahead, two end rungs
}

TEST(CutFront, LensWithSharedEndsEmitsNoDegenerateTriangle) {
  std::vector<V> X = {V(0, 0, 0), V(1, -0.2, 0), V(2, -0.2, 0), V(3, 0, 0), V(1.5, 1, 0)};
  std::vector<std::array<int, 3>> tris;
  appendStrip(
      {0, 1, 2, 3}, {0, 4, 3}, [&](int v) { return X[static_cast<std::size_t>(v)]; }, tris);
  ASSERT_EQ(tris.size(), 3u);  // a pentagon
  for (const auto& t : tris) {
    EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
    const V n = (X[static_cast<std::size_t>(t[1])] - X[static_cast<std::size_t>(t[0])])
                    .cross(X[static_cast<std::size_t>(t[2])] - X[static_cast<std::size_t>(t[0])]);
    EXPECT_GT(n.z(), 0.0);
  }
}

TEST(CutFront, UnevenlySpacedChainsGetNoFan) {
  // behind: 21 vertices bunched in x in [0, 0.02] then one at x = 4; ahead: 6 evenly spaced
  // over [0, 4] at y = 1. Paired by arc length alone, the bunch would all meet ahead's first
  // vertex; runs along one chain stop at twice the segment ratio (2 x 4 + 1 = 9).
  std::vector<V> X;
  std::vector<int> behind, ahead;
  for (int i = 0; i < 20; ++i) {
    behind.push_back(static_cast<int>(X.size()));
    X.emplace_back(0.001 * i, 0.0, 0.0);
  }
  behind.push_back(static_cast<int>(X.size()));
  X.emplace_back(4.0, 0.0, 0.0);
  for (int j = 0; j < 6; ++j) {
    ahead.push_back(static_cast<int>(X.size()));
    X.emplace_back(0.8 * j, 1.0, 0.0);
  }
  std::vector<std::array<int, 3>> tris;
  appendStrip(
      behind, ahead, [&](int v) { return X[static_cast<std::size_t>(v)]; }, tris);
  ASSERT_EQ(tris.size(), 21u + 6u - 2u);
  std::map<int, int> fan;
  for (const auto& t : tris)
    for (int v : t) ++fan[v];
  for (const auto& [v, n] : fan) EXPECT_LE(n, 11) << "vertex " << v;
  EXPECT_EQ(directedEdges(tris).size(), 3 * tris.size());  // no edge used twice one way
}

TEST(CutFront, GradingHalvesTheDenseChainUntilItIsAtMostTwiceTheOtherPlusTwo) {
  EXPECT_EQ(gradingLevels(8, 3), 0);     // 8 <= 2 x 3 + 2
  EXPECT_EQ(gradingLevels(9, 3), 1);     // 9 -> 5
  EXPECT_EQ(gradingLevels(100, 5), 4);   // 100 -> 51 -> 26 -> 14 -> 8
  EXPECT_EQ(gradingLevels(1000, 1), 9);  // 1000 -> 501 -> ... -> 9 -> 5 -> 3
}

TEST(CutFront, HalvingRowStandsOverEverySecondVertexPartWayToTheOtherChain) {
  // behind along x at y = 0 (x = 0..6, 7 vertices), ahead along x at y = 2 over [0, 12]: the
  // point of ahead at behind's normalised arc length u = x / 6 is (12 u, 2).
  std::vector<V> X;
  for (int i = 0; i < 7; ++i) X.emplace_back(i, 0.0, 0.0);
  X.emplace_back(0.0, 2.0, 0.0);
  X.emplace_back(3.0, 2.0, 0.0);
  X.emplace_back(12.0, 2.0, 0.0);
  const auto rest = [&](int v) { return X[static_cast<std::size_t>(v)]; };
  const std::vector<Eigen::Vector3d> row = halvingRow({0, 1, 2, 3, 4, 5, 6}, {7, 8, 9}, rest, 0.25);
  ASSERT_EQ(row.size(), 2u);  // over behind's vertices 2 and 4 (6 is behind's last)
  for (std::size_t k = 0; k < row.size(); ++k) {
    const double x = 2.0 * static_cast<double>(k + 1), on_ahead = 12.0 * x / 6.0;
    EXPECT_NEAR(row[k].x(), 0.75 * x + 0.25 * on_ahead, 1e-12);
    EXPECT_NEAR(row[k].y(), 0.25 * 2.0, 1e-12);
  }
}

TEST(CutFront, SegmentCountSplitsAboveWidthMergesBelowHalfAndKeepsItBetween) {
  EXPECT_EQ(frontSegmentCount(1.0, 2, 0.3), 4);   // 0.5 > w -> split until 0.25
  EXPECT_EQ(frontSegmentCount(1.1, 4, 0.3), 4);   // 0.275 in [w/2, w]: unchanged
  EXPECT_EQ(frontSegmentCount(0.5, 4, 0.3), 3);   // 0.125 < w/2 -> merge to 0.1667
  EXPECT_EQ(frontSegmentCount(0.01, 6, 0.3), 2);  // never below two segments
}

}  // namespace
}  // namespace surgical_sim::core
