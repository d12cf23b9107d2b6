#include <gtest/gtest.h>

#include "surgical_sim/core/robot/resample_polyline.h"

namespace surgical_sim::core {
namespace {

// An L-shaped path of 0.3 m + 0.4 m at 0.1 m spacing: 8 points 0.1 m apart, one on the corner,
// ending exactly at the last waypoint.
TEST(ResamplePolyline, EquallySpacedAlongTheArcAndEndsAtTheLastPoint) {
  const std::vector<Eigen::Vector3d> points = {{0.0, 0.0, 0.0}, {0.3, 0.0, 0.0}, {0.3, 0.4, 0.0}};
  const std::vector<Eigen::Vector3d> out = resamplePolyline(points, 0.1);
  ASSERT_EQ(out.size(), 8u);
  EXPECT_LT((out.front() - points.front()).norm(), 1e-15);
  EXPECT_LT((out.back() - points.back()).norm(), 1e-12);
  EXPECT_LT((out[3] - Eigen::Vector3d(0.3, 0.0, 0.0)).norm(), 1e-12);
  for (size_t i = 1; i < out.size(); ++i) EXPECT_NEAR((out[i] - out[i - 1]).norm(), 0.1, 1e-12);
  // A spacing that does not divide the length: the last point is appended.
  EXPECT_EQ(resamplePolyline(points, 0.3).size(), 4u);
  EXPECT_EQ(resamplePolyline({points[1]}, 0.1).size(), 1u);
}

TEST(ResamplePolyline, RejectsBadInput) {
  EXPECT_THROW(resamplePolyline({}, 0.1), std::invalid_argument);
  EXPECT_THROW(resamplePolyline({Eigen::Vector3d(NAN, 0, 0)}, 0.1), std::invalid_argument);
  EXPECT_THROW(resamplePolyline({Eigen::Vector3d::Zero()}, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
