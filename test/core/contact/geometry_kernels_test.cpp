#include <gtest/gtest.h>

#include <random>

#include "surgical_sim/core/contact/closest_point_on_segment.h"
#include "surgical_sim/core/contact/closest_point_on_triangle.h"
#include "surgical_sim/core/contact/closest_points_segment_segment.h"
#include "surgical_sim/core/contact/closest_points_segment_triangle.h"

namespace surgical_sim::core {
namespace {

constexpr int kSamples = 60;

Eigen::Vector3d randomPoint(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return {u(rng), u(rng), u(rng)};
}

/// Brute-force squared distance of a point to a triangle by sampling barycentric coordinates.
double sampledTriangleDistance(const Eigen::Vector3d& v0, const Eigen::Vector3d& v1,
                               const Eigen::Vector3d& v2, const Eigen::Vector3d& p) {
  double best = 1e300;
  for (int i = 0; i <= kSamples; ++i) {
    for (int j = 0; i + j <= kSamples; ++j) {
      const double u = static_cast<double>(i) / kSamples;
      const double v = static_cast<double>(j) / kSamples;
      best = std::min(best, ((1 - u - v) * v0 + u * v1 + v * v2 - p).squaredNorm());
    }
  }
  return best;
}

TEST(ClosestPointOnSegment, MatchesSamplingAndHandlesDegenerateSegment) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d a = randomPoint(rng), b = randomPoint(rng), p = randomPoint(rng);
    const SegmentPointClosest c = closestPointOnSegment(a, b, p);
    double best = 1e300;
    for (int i = 0; i <= 1000; ++i) best = std::min(best, (a + i / 1000.0 * (b - a) - p).norm());
    EXPECT_LE(std::sqrt(c.distance_squared), best + 1e-12);
    EXPECT_GE(std::sqrt(c.distance_squared), best - 2e-3);
  }
  const SegmentPointClosest point = closestPointOnSegment({1, 2, 3}, {1, 2, 3}, {0, 0, 0});
  EXPECT_EQ(point.t, 0.0);
  EXPECT_NEAR(point.distance_squared, 14.0, 1e-14);
}

TEST(ClosestPointOnTriangle, MatchesSamplingInEveryRegion) {
  std::mt19937 rng(2);
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Vector3d v0 = randomPoint(rng), v1 = randomPoint(rng), v2 = randomPoint(rng);
    const Eigen::Vector3d p = 1.5 * randomPoint(rng);
    const TrianglePointClosest c = closestPointOnTriangle(v0, v1, v2, p);
    const double sampled = std::sqrt(sampledTriangleDistance(v0, v1, v2, p));
    const double exact = std::sqrt(c.distance_squared);
    EXPECT_LE(exact, sampled + 1e-12);
    EXPECT_GE(exact, sampled - 0.05);
    EXPECT_NEAR(c.barycentric.sum(), 1.0, 1e-12);
    EXPECT_GE(c.barycentric.minCoeff(), -1e-12);
  }
}

TEST(ClosestPointOnTriangle, DegenerateTriangleIsItsEdges) {
  const TrianglePointClosest c =
      closestPointOnTriangle({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1.5, 1.0, 0.0});
  EXPECT_NEAR(c.distance_squared, 1.0, 1e-14);
  EXPECT_TRUE(c.point.isApprox(Eigen::Vector3d(1.5, 0, 0)));
}

TEST(ClosestPointsSegmentSegment, MatchesSamplingAndHandlesParallelAndPoints) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d p0 = randomPoint(rng), p1 = randomPoint(rng);
    const Eigen::Vector3d q0 = randomPoint(rng), q1 = randomPoint(rng);
    const SegmentSegmentClosest c = closestPointsSegmentSegment(p0, p1, q0, q1);
    double best = 1e300;
    for (int i = 0; i <= 200; ++i)
      for (int j = 0; j <= 200; ++j)
        best = std::min(best, (p0 + i / 200.0 * (p1 - p0) - q0 - j / 200.0 * (q1 - q0)).norm());
    EXPECT_LE(std::sqrt(c.distance_squared), best + 1e-12);
    EXPECT_GE(std::sqrt(c.distance_squared), best - 1e-2);
  }
  // Parallel, overlapping: distance 1.
  const SegmentSegmentClosest parallel =
      closestPointsSegmentSegment({0, 0, 0}, {2, 0, 0}, {1, 1, 0}, {3, 1, 0});
  EXPECT_NEAR(parallel.distance_squared, 1.0, 1e-14);
  // Parallel, disjoint along the axis: end to end.
  const SegmentSegmentClosest apart =
      closestPointsSegmentSegment({0, 0, 0}, {1, 0, 0}, {3, 1, 0}, {4, 1, 0});
  EXPECT_NEAR(apart.distance_squared, 5.0, 1e-14);
  // Both points.
  EXPECT_NEAR(
      closestPointsSegmentSegment({0, 0, 0}, {0, 0, 0}, {0, 3, 4}, {0, 3, 4}).distance_squared,
      25.0, 1e-14);
}

TEST(ClosestPointsSegmentTriangle, MatchesSampling) {
  std::mt19937 rng(4);
  for (int trial = 0; trial < 150; ++trial) {
    const Eigen::Vector3d v0 = randomPoint(rng), v1 = randomPoint(rng), v2 = randomPoint(rng);
    const Eigen::Vector3d a = 1.5 * randomPoint(rng), b = 1.5 * randomPoint(rng);
    const SegmentTriangleClosest c = closestPointsSegmentTriangle(a, b, v0, v1, v2);
    double best = 1e300;
    for (int i = 0; i <= 40; ++i) {
      best = std::min(best, sampledTriangleDistance(v0, v1, v2, a + i / 40.0 * (b - a)));
    }
    const double exact = std::sqrt(c.distance_squared);
    EXPECT_LE(exact, std::sqrt(best) + 1e-12);
    EXPECT_GE(exact, std::sqrt(best) - 0.08);
    EXPECT_NEAR((c.point_segment - c.point_triangle).norm(), exact, 1e-12);
    EXPECT_NEAR(c.barycentric.sum(), 1.0, 1e-12);
  }
}

TEST(ClosestPointsSegmentTriangle, CrossingParallelAndDegenerateCases) {
  const Eigen::Vector3d v0(0, 0, 0), v1(1, 0, 0), v2(0, 1, 0);
  const SegmentTriangleClosest crossing =
      closestPointsSegmentTriangle({0.2, 0.2, 1.0}, {0.2, 0.2, -1.0}, v0, v1, v2);
  EXPECT_TRUE(crossing.intersects);
  EXPECT_NEAR(crossing.t, 0.5, 1e-14);
  EXPECT_TRUE(crossing.barycentric.isApprox(Eigen::Vector3d(0.6, 0.2, 0.2)));
  // Parallel above the interior.
  const SegmentTriangleClosest parallel =
      closestPointsSegmentTriangle({0.1, 0.1, 0.5}, {0.3, 0.1, 0.5}, v0, v1, v2);
  EXPECT_NEAR(parallel.distance_squared, 0.25, 1e-14);
  // In-plane, outside the triangle: nearest to the hypotenuse.
  const SegmentTriangleClosest in_plane =
      closestPointsSegmentTriangle({1, 1, 0}, {2, 1, 0}, v0, v1, v2);
  EXPECT_NEAR(in_plane.distance_squared, 0.5, 1e-14);
  // Point segment and zero-area triangle.
  const SegmentTriangleClosest degenerate =
      closestPointsSegmentTriangle({0.5, 1, 0}, {0.5, 1, 0}, v0, v1, {2, 0, 0});
  EXPECT_NEAR(degenerate.distance_squared, 1.0, 1e-14);
}

}  // namespace
}  // namespace surgical_sim::core
