#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "surgical_sim/core/cutting/edge_sweep_ccd.h"

namespace surgical_sim::core {
namespace {

using V = Eigen::Vector3d;

TEST(EdgeSweepCcd, CubicMatchesTheTripleProductAtAnyTime) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto r = [&] { return V(u(rng), u(rng), u(rng)); };
  const V b0s = r(), b1s = r(), b0e = r(), b1e = r(), e0s = r(), e1s = r(), e0e = r(), e1e = r();
  const Eigen::Vector4d c = coplanarityCubic(b0s, b1s, b0e, b1e, e0s, e1s, e0e, e1e);
  for (double t : {0.0, 0.3, 0.77, 1.0}) {
    auto at = [t](const V& a, const V& b) { return V(a + t * (b - a)); };
    const V b0 = at(b0s, b0e), b1 = at(b1s, b1e), e0 = at(e0s, e0e), e1 = at(e1s, e1e);
    const double direct = (b1 - b0).cross(e0 - b0).dot(e1 - b0);
    EXPECT_NEAR(c[0] + t * c[1] + t * t * c[2] + t * t * t * c[3], direct, 1e-12);
  }
}

TEST(EdgeSweepCcd, FastBladeCrossingAStaticEdgeIsFoundWithTimeAndParameters) {
  // Blade along y at x = -1 moves to x = +1; static edge along z at x = 0.5, y = 0.25.
  const auto hit =
      edgeSweepCrossing(V(-1, -1, 0), V(-1, 1, 0), V(1, -1, 0), V(1, 1, 0), V(0.5, 0.25, -1),
                        V(0.5, 0.25, 3), V(0.5, 0.25, -1), V(0.5, 0.25, 3), 1e-9);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 0.75, 1e-9);   // x(t) = -1 + 2 t = 0.5
  EXPECT_NEAR(hit->s, 0.25, 1e-9);   // z = 0 is a quarter of the way from -1 to 3
  EXPECT_NEAR(hit->u, 0.625, 1e-9);  // y = 0.25 from -1 to 1
}

TEST(EdgeSweepCcd, StaticBladeWithTissueMovingThroughItIsFound) {
  const auto hit = edgeSweepCrossing(V(0, -1, 0), V(0, 1, 0), V(0, -1, 0), V(0, 1, 0), V(-2, 0, -1),
                                     V(-2, 0, 1), V(2, 0, -1), V(2, 0, 1), 1e-9);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 0.5, 1e-9);
  EXPECT_NEAR(hit->s, 0.5, 1e-9);
}

TEST(EdgeSweepCcd, EdgeEnteringTheSweptAreaAfterTheBladePassedIsNotCut) {
  // The blade moves from x = 0 to x = 1; the edge starts behind it and follows it into the swept
  // area, but more slowly (Magnoux's situation 2).
  const auto miss =
      edgeSweepCrossing(V(0, -1, 0), V(0, 1, 0), V(1, -1, 0), V(1, 1, 0), V(-0.5, 0, 0.5),
                        V(-0.5, 0, 2), V(0.9, 0, 0.5), V(0.9, 0, 2), 1e-9);
  EXPECT_FALSE(miss);  // x_edge(t) = -0.5 + 1.4 t never reaches x_blade(t) = t
  const auto parallel = edgeSweepCrossing(V(0, -1, 0), V(0, 1, 0), V(0, -1, 1), V(0, 1, 1),
                                          V(1, -1, 0), V(1, 1, 0), V(1, -1, 0), V(1, 1, 0), 1e-9);
  EXPECT_FALSE(parallel);
}

TEST(EdgeSweepCcd, EdgeGrazedByTheBladeTipIsFound) {
  // Blade from the origin to a tip moving from (0.5, -0.5, 0) to (0.5, 0.5, 0): the tip passes
  // through the edge along z at (0.5, 0) at t = 0.5.
  const auto hit =
      edgeSweepCrossing(V(0, 0, 0), V(0.5, -0.5, 0), V(0, 0, 0), V(0.5, 0.5, 0), V(0.5, 0, -1),
                        V(0.5, 0, 1), V(0.5, 0, -1), V(0.5, 0, 1), 1e-9);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 0.5, 1e-9);
  EXPECT_NEAR(hit->u, 1.0, 1e-9);
}

}  // namespace
}  // namespace surgical_sim::core
