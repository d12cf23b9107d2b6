// computeSignedSvd and computeSignedRotation on random, near-identity, rank-deficient,
// repeated-singular-value and inverted deformation gradients.

#include "surgical_sim/core/tissue/signed_svd.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <random>
#include <vector>

namespace surgical_sim::core {
namespace {

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

// Q1 diag(s) Q2^T with random rotations Q1, Q2.
Eigen::Matrix3d withSingularValues(const Eigen::Vector3d& s, std::mt19937& rng) {
  return randomRotation(rng) * s.asDiagonal() * randomRotation(rng).transpose();
}

Eigen::Matrix3d randomMatrix(double amplitude, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  Eigen::Matrix3d A;
  for (int i = 0; i < 9; ++i) A.data()[i] = u(rng);
  return A;
}

// The deformation gradients of every class, several of each, at scales 1e-3, 1 and 1e3.
std::vector<Eigen::Matrix3d> testMatrices() {
  std::mt19937 rng(5);
  std::vector<Eigen::Matrix3d> unit;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  unit.push_back(I);
  unit.push_back(Eigen::Matrix3d::Zero());
  for (int k = 0; k < 20; ++k) {
    unit.push_back(randomMatrix(1.0, rng));                                     // random
    unit.push_back(I + randomMatrix(1e-9, rng));                                // near identity
    unit.push_back(randomRotation(rng) * (I + randomMatrix(1e-3, rng)));        // near rotation
    unit.push_back(withSingularValues(Eigen::Vector3d(1.5, 0.7, 0.0), rng));    // rank 2
    unit.push_back(withSingularValues(Eigen::Vector3d(2.0, 0.0, 0.0), rng));    // rank 1
    unit.push_back(withSingularValues(Eigen::Vector3d(1.3, 1.3, 0.4), rng));    // repeated
    unit.push_back(withSingularValues(Eigen::Vector3d(2.0, 0.5, 0.5), rng));    // repeated
    unit.push_back(withSingularValues(Eigen::Vector3d(0.8, 0.8, 0.8), rng));    // scaled rotation
    unit.push_back(withSingularValues(Eigen::Vector3d(1.2, 1.0, -0.3), rng));   // inverted
    unit.push_back(withSingularValues(Eigen::Vector3d(1.0, 1.0, -1.0), rng));   // reflection
    unit.push_back(withSingularValues(Eigen::Vector3d(1.1, 0.9, -1e-7), rng));  // barely inverted
    unit.push_back(withSingularValues(Eigen::Vector3d(1.0, 1e-3, 1e-4), rng));  // near rank 1
  }
  std::vector<Eigen::Matrix3d> all;
  for (double scale : {1e-3, 1.0, 1e3}) {
    for (const Eigen::Matrix3d& F : unit) all.push_back(scale * F);
  }
  return all;
}

TEST(SignedSvd, ReconstructsWithProperRotationsAndSignedSmallestValue) {
  for (const Eigen::Matrix3d& F : testMatrices()) {
    const SignedSvd svd = computeSignedSvd(F);
    const double scale = std::max(F.norm(), 1e-300);
    EXPECT_LT((svd.U * svd.s.asDiagonal() * svd.V.transpose() - F).norm(), 1e-12 * scale) << F;
    for (const Eigen::Matrix3d& Q : {svd.U, svd.V}) {
      EXPECT_LT((Q.transpose() * Q - Eigen::Matrix3d::Identity()).norm(), 1e-12) << F;
      EXPECT_NEAR(Q.determinant(), 1.0, 1e-12) << F;
    }
    EXPECT_GE(svd.s(0), svd.s(1) - 1e-12 * scale) << F;
    EXPECT_GE(svd.s(1), std::abs(svd.s(2)) - 1e-12 * scale) << F;
    EXPECT_GE(svd.s(1), -1e-12 * scale) << F;
    const double det = F.determinant();
    if (std::abs(det) > 1e-9 * scale * scale * scale) {
      EXPECT_EQ(svd.s(2) < 0.0, det < 0.0) << F;
    } else {
      EXPECT_LT(std::abs(svd.s(2)), 1e-8 * scale) << F;
    }
  }
}

TEST(SignedSvd, RotationEqualsTheSvdRotation) {
  for (const Eigen::Matrix3d& F : testMatrices()) {
    const SignedSvd svd = computeSignedSvd(F);
    const Eigen::Matrix3d R = computeSignedRotation(F);
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-12) << F;
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12) << F;
    // R is unique where no two signed singular values sum to (nearly) zero.
    if (svd.s(1) + svd.s(2) > 1e-3 * svd.s(0)) {
      EXPECT_LT((R - svd.U * svd.V.transpose()).norm(), 1e-12) << F;
    }
  }
}

TEST(SignedSvd, RotationOfARotatedStretchIsTheRotation) {
  std::mt19937 rng(6);
  for (int k = 0; k < 20; ++k) {
    const Eigen::Matrix3d Q = randomRotation(rng);
    const Eigen::Matrix3d S = Eigen::Vector3d(1.4, 0.9, 0.6).asDiagonal();
    const Eigen::Matrix3d W = randomRotation(rng);
    const Eigen::Matrix3d F = Q * W * S * W.transpose();  // polar: Q times symmetric stretch
    EXPECT_LT((computeSignedRotation(F) - Q).norm(), 1e-12);
  }
}

}  // namespace
}  // namespace surgical_sim::core
