#include "surgical_sim/core/tissue/efg_shape_functions.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

namespace surgical_sim::core {
namespace {

// The 8 corners of the cube [0, 2]^3 plus `extra` random points in [-1, 3]^3, all jittered by
// up to 0.2, scaled by `scale` [m].
Eigen::Matrix3Xd neighbourhood(int extra, double scale, std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  std::uniform_real_distribution<double> wide(-1.0, 3.0);
  Eigen::Matrix3Xd points(3, 8 + extra);
  for (int v = 0; v < 8; ++v) {
    points.col(v) = 2.0 * Eigen::Vector3d(v & 1, (v >> 1) & 1, (v >> 2) & 1) +
                    Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
  }
  for (int v = 8; v < 8 + extra; ++v)
    points.col(v) = Eigen::Vector3d(wide(rng), wide(rng), wide(rng));
  return scale * points;
}

TEST(QuarticSplineKernel, IsOneAtCentreZeroAtSupportAndNormalised) {
  EXPECT_DOUBLE_EQ(quarticSplineKernel(0.0), 1.0);
  EXPECT_NEAR(quarticSplineKernel(1.0), 0.0, 1e-15);
  EXPECT_EQ(quarticSplineKernel(1.5), 0.0);
  // 4 pi int_0^1 s^2 w(s) ds = 16 pi / 105 (so 105 / (16 pi h^3) w integrates to 1): midpoint rule.
  const int n = 20000;
  double integral = 0.0;
  for (int i = 0; i < n; ++i) {
    const double s = (i + 0.5) / n;
    integral += 4.0 * M_PI * s * s * quarticSplineKernel(s) / n;
  }
  EXPECT_NEAR(integral, 16.0 * M_PI / 105.0, 1e-8);
  // Monotone decreasing on [0, 1].
  for (int i = 1; i <= 100; ++i) {
    EXPECT_LT(quarticSplineKernel(i / 100.0), quarticSplineKernel((i - 1) / 100.0));
  }
}

TEST(MlsShapeFunctions, PartitionOfUnityAndLinearReproduction) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> inside(0.3, 1.7);
  for (int extra : {0, 4, 8}) {
    for (int trial = 0; trial < 10; ++trial) {
      const Eigen::Matrix3Xd points = neighbourhood(extra, 1.0, rng);
      const Eigen::Vector3d x(inside(rng), inside(rng), inside(rng));
      const MlsShapeFunctions mls = computeMlsShapeFunctions(x, points, 8.0);
      ASSERT_EQ(mls.status, MlsStatus::Ok);
      EXPECT_NEAR(mls.phi.sum(), 1.0, 1e-13);
      EXPECT_LT((points * mls.phi - x).norm(), 1e-13);
      // Gradients: sum grad = 0 and sum x_i grad_i^T = I (a linear field's gradient is exact).
      EXPECT_LT(mls.grad.colwise().sum().norm(), 1e-12);
      EXPECT_LT((points * mls.grad - Eigen::Matrix3d::Identity()).norm(), 1e-12);
      // Any linear field u(y) = c + B y is reproduced with its gradient.
      const Eigen::Vector3d c(0.3, -1.2, 2.0);
      Eigen::Matrix3d B;
      B << 1.0, 0.5, -0.2, 0.1, -2.0, 0.7, 0.4, 0.3, 0.9;
      const Eigen::Matrix3Xd u = (B * points).colwise() + c;
      EXPECT_LT((u * mls.phi - (B * x + c)).norm(), 1e-12);
      EXPECT_LT((u * mls.grad - B).norm(), 1e-12);
      EXPECT_LT(mls.condition, 1e4);
    }
  }
}

TEST(MlsShapeFunctions, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(5);
  for (int extra : {0, 8}) {
    const Eigen::Matrix3Xd points = neighbourhood(extra, 1.0, rng);
    const Eigen::Vector3d x(0.6, 1.1, 0.9);
    const MlsShapeFunctions mls = computeMlsShapeFunctions(x, points, 8.0);
    ASSERT_EQ(mls.status, MlsStatus::Ok);
    const double h = 1e-6;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d dx = h * Eigen::Vector3d::Unit(c);
      const Eigen::VectorXd fd = (computeMlsShapeFunctions(x + dx, points, 8.0).phi -
                                  computeMlsShapeFunctions(x - dx, points, 8.0).phi) /
                                 (2.0 * h);
      EXPECT_LT((fd - mls.grad.col(c)).norm(), 1e-4 * mls.grad.col(c).norm()) << c;
    }
  }
}

TEST(MlsShapeFunctions, ScaleInvariant) {
  std::mt19937 rng(7);
  const Eigen::Matrix3Xd points = neighbourhood(4, 1.0, rng);
  const Eigen::Vector3d x(0.7, 0.8, 1.3);
  const MlsShapeFunctions m = computeMlsShapeFunctions(x, points, 8.0);
  const MlsShapeFunctions mm = computeMlsShapeFunctions(1e-3 * x, 1e-3 * points, 8e-3);
  ASSERT_EQ(mm.status, MlsStatus::Ok);
  EXPECT_LT((m.phi - mm.phi).norm(), 1e-12);
  EXPECT_LT((m.grad - 1e-3 * mm.grad).norm(), 1e-12 * m.grad.norm());
  EXPECT_NEAR(m.condition, mm.condition, 1e-9 * m.condition);
}

TEST(MlsShapeFunctions, DegenerateNeighbourhoodGivesStatusNotNaN) {
  // 9 coplanar points (z = 0): the linear basis cannot be fitted.
  Eigen::Matrix3Xd plane(3, 9);
  for (int i = 0; i < 9; ++i) plane.col(i) = Eigen::Vector3d(i % 3, i / 3, 0.0);
  const MlsShapeFunctions flat =
      computeMlsShapeFunctions(Eigen::Vector3d(1.0, 1.0, 0.3), plane, 8.0);
  EXPECT_EQ(flat.status, MlsStatus::IllConditioned);
  EXPECT_EQ(flat.phi.size(), 0);
  EXPECT_STREQ(toString(flat.status), "ill_conditioned");

  EXPECT_EQ(computeMlsShapeFunctions(Eigen::Vector3d::Zero(), plane.leftCols(3), 8.0).status,
            MlsStatus::TooFewPoints);
  Eigen::Matrix3Xd bad = plane;
  bad(1, 4) = NAN;
  EXPECT_EQ(computeMlsShapeFunctions(Eigen::Vector3d::Zero(), bad, 8.0).status,
            MlsStatus::NonFinite);
  // No support.
  EXPECT_EQ(
      computeMlsShapeFunctions(Eigen::Vector3d::Zero(), Eigen::Matrix3Xd::Zero(3, 8), 0.0).status,
      MlsStatus::IllConditioned);
}

}  // namespace
}  // namespace surgical_sim::core
