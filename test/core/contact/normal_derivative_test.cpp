#include "surgical_sim/core/contact/normal_derivative.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace surgical_sim::core {
namespace {

Eigen::Vector3d normalAt(const Eigen::Vector3d& u, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b, const Eigen::Vector3d& v0,
                         const Eigen::Vector3d& v1, const Eigen::Vector3d& v2) {
  const SegmentTriangleClosest c = closestPointsSegmentTriangle(a + u, b + u, v0, v1, v2);
  return (c.point_triangle - c.point_segment).normalized();
}

/// Central differences of n over random tool translations, for every closest-feature pair the
/// random placements produce (vertex, edge and face points against the tip or the shaft).
TEST(NormalTranslationDerivative, MatchesFiniteDifferencesOverRandomPlacements) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double h = 1e-7;  // [m] for a 1e-2 m scene
  int checked = 0, vertex = 0, edge = 0, face = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Vector3d v0(0.0, 0.0, 0.0), v1(0.01, 0.0, 0.0), v2(0.002, 0.012, 0.0);
    const Eigen::Vector3d a(0.03 * u(rng), 0.03 * u(rng), 0.001 + 0.01 * std::abs(u(rng)));
    const Eigen::Vector3d b = a + 0.02 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    const SegmentTriangleClosest closest = closestPointsSegmentTriangle(a, b, v0, v1, v2);
    if (closest.intersects || closest.distance_squared < 1e-8) continue;
    const Eigen::Matrix3d analytic = normalTranslationDerivative(closest, a, b, v0, v1, v2);
    Eigen::Matrix3d numeric;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(k);
      numeric.col(k) = (normalAt(e, a, b, v0, v1, v2) - normalAt(-e, a, b, v0, v1, v2)) / (2.0 * h);
    }
    // Skip placements straddling a feature switch within +-h (the derivative jumps there).
    const SegmentTriangleClosest plus = closestPointsSegmentTriangle(
        a + h * Eigen::Vector3d::Ones(), b + h * Eigen::Vector3d::Ones(), v0, v1, v2);
    if ((plus.barycentric.array() > 0.0).count() != (closest.barycentric.array() > 0.0).count()) {
      continue;
    }
    const int support = static_cast<int>((closest.barycentric.array() > 1e-12).count());
    vertex += support == 1;
    edge += support == 2;
    face += support == 3;
    ++checked;
    EXPECT_LE((analytic - numeric).norm(), 1e-5 * (1.0 + analytic.norm()))
        << "trial " << trial << "\nanalytic\n"
        << analytic << "\nnumeric\n"
        << numeric;
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(vertex, 20);
  EXPECT_GT(edge, 20);
  EXPECT_GT(face, 20);
}

TEST(NormalTranslationDerivative, TipOnAVertexRotatesLikeAPoint) {
  // Sphere-tip centre 3 mm straight above a vertex: n = -z; moving the tool by x tilts n by
  // -x / d, moving it along n does not rotate it.
  const Eigen::Vector3d v0(0.0, 0.0, 0.0), v1(-0.01, 0.01, 0.0), v2(-0.01, -0.01, 0.0);
  const Eigen::Vector3d a(0.0, 0.0, 0.003), b(0.0, 0.0, 0.05);
  const SegmentTriangleClosest closest = closestPointsSegmentTriangle(a, b, v0, v1, v2);
  const Eigen::Matrix3d dn = normalTranslationDerivative(closest, a, b, v0, v1, v2);
  EXPECT_NEAR(dn(0, 0), -1.0 / 0.003, 1e-9);
  EXPECT_NEAR(dn(1, 1), -1.0 / 0.003, 1e-9);
  EXPECT_NEAR(dn(2, 2), 0.0, 1e-9);
}

TEST(NormalTranslationDerivative, FaceContactDoesNotRotate) {
  const Eigen::Vector3d v0(-0.01, -0.01, 0.0), v1(0.01, -0.01, 0.0), v2(0.0, 0.01, 0.0);
  const Eigen::Vector3d a(0.0, 0.0, 0.002), b(0.0, 0.0, 0.05);
  const SegmentTriangleClosest closest = closestPointsSegmentTriangle(a, b, v0, v1, v2);
  EXPECT_LE(normalTranslationDerivative(closest, a, b, v0, v1, v2).norm(), 1e-12);
}

TEST(FaceNormalDerivative, MatchesFiniteDifferencesOfTheUnitNormal) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  const double h = 1e-8;  // [m]
  const auto normal = [](const Eigen::Matrix<double, 9, 1>& v) {
    return (v.segment<3>(3) - v.segment<3>(0))
        .cross(v.segment<3>(6) - v.segment<3>(0))
        .normalized();
  };
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Matrix<double, 9, 1> v;
    for (int k = 0; k < 9; ++k) v[k] = u(rng);
    const Eigen::Matrix<double, 3, 9> analytic =
        faceNormalDerivative(v.segment<3>(0), v.segment<3>(3), v.segment<3>(6));
    for (int k = 0; k < 9; ++k) {
      Eigen::Matrix<double, 9, 1> plus = v, minus = v;
      plus[k] += h;
      minus[k] -= h;
      const Eigen::Vector3d numeric = (normal(plus) - normal(minus)) / (2.0 * h);
      EXPECT_LE((analytic.col(k) - numeric).norm(), 1e-5 * (1.0 + numeric.norm()))
          << "trial " << trial << " coordinate " << k;
    }
  }
  // A translated or in-plane-stretched triangle keeps its normal: rows sum to zero per axis.
  const Eigen::Matrix<double, 3, 9> d = faceNormalDerivative(
      Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.01, 0, 0), Eigen::Vector3d(0, 0.01, 0));
  EXPECT_LE((d.middleCols<3>(0) + d.middleCols<3>(3) + d.middleCols<3>(6)).norm(), 1e-9);
  // Lifting v1 by dz tilts the normal of the xy triangle towards -x by dz / |e1|.
  EXPECT_NEAR(d(0, 5), -100.0, 1e-9);
}

}  // namespace
}  // namespace surgical_sim::core
