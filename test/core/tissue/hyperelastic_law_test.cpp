#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "surgical_sim/core/tissue/corotational_law.h"
#include "surgical_sim/core/tissue/psd_projection.h"
#include "surgical_sim/core/tissue/signed_svd.h"
#include "surgical_sim/core/tissue/st_venant_kirchhoff_law.h"
#include "surgical_sim/core/tissue/stable_neo_hookean_law.h"
#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

Eigen::Matrix<double, 9, 1> vec(const Eigen::Matrix3d& A) {
  return Eigen::Map<const Eigen::Matrix<double, 9, 1>>(A.data());
}

// Linear isotropic elasticity tensor C(i+3j, k+3l) = lambda d_ij d_kl + mu (d_ik d_jl + d_il d_jk).
Matrix9d linearTensor(double mu, double lambda) {
  Matrix9d C = Matrix9d::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l)
          C(i + 3 * j, k + 3 * l) =
              lambda * (i == j) * (k == l) + mu * ((i == k) * (j == l) + (i == l) * (j == k));
  return C;
}

Eigen::Matrix3d randomF(std::mt19937& rng, double amplitude, bool inverted) {
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  for (int i = 0; i < 9; ++i) F.data()[i] += u(rng);
  if (inverted) F.col(2) *= -0.6;
  return F;
}

std::unique_ptr<HyperelasticLaw> makeLaw(int which, const Material& m) {
  if (which == 0) return std::make_unique<CorotationalLaw>(m);
  if (which == 1) return std::make_unique<StVenantKirchhoffLaw>(m);
  return std::make_unique<StableNeoHookeanLaw>(m);
}

class LawTest : public ::testing::TestWithParam<int> {
 protected:
  Material material = test::testMaterial(0.3);
  std::unique_ptr<HyperelasticLaw> law = makeLaw(GetParam(), material);
  bool invertible() const { return law->name() != "svk"; }
};

TEST_P(LawTest, FirstPiolaIsEnergyGradient) {
  std::mt19937 rng(7);
  for (bool inverted : {false, true}) {
    if (inverted && !invertible()) continue;
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::Matrix3d F = randomF(rng, 0.3, inverted);
      Eigen::Matrix3d fd;
      const double h = 1e-6;
      for (int k = 0; k < 9; ++k) {
        Eigen::Matrix3d Fp = F, Fm = F;
        Fp.data()[k] += h;
        Fm.data()[k] -= h;
        fd.data()[k] = (law->energyDensity(Fp) - law->energyDensity(Fm)) / (2 * h);
      }
      EXPECT_LT((law->firstPiola(F) - fd).norm(), 1e-6 * fd.norm()) << law->name();
    }
  }
}

TEST_P(LawTest, ExactTangentIsFirstPiolaJacobian) {
  std::mt19937 rng(11);
  for (bool inverted : {false, true}) {
    if (inverted && !invertible()) continue;
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::Matrix3d F = randomF(rng, 0.3, inverted);
      Matrix9d fd;
      const double h = 1e-6;
      for (int k = 0; k < 9; ++k) {
        Eigen::Matrix3d Fp = F, Fm = F;
        Fp.data()[k] += h;
        Fm.data()[k] -= h;
        fd.col(k) = vec(law->firstPiola(Fp) - law->firstPiola(Fm)) / (2 * h);
      }
      const Matrix9d A = law->firstPiolaDerivative(F);
      EXPECT_LT((A - fd).norm(), 1e-6 * fd.norm()) << law->name();
      EXPECT_LT((A - A.transpose()).norm(), 1e-12 * A.norm()) << law->name();
      EXPECT_EQ(law->tangent(F, TangentMode::Exact), A);
    }
  }
}

TEST_P(LawTest, RestStateIsStressFreeAndLinearisesToHooke) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  EXPECT_NEAR(law->energyDensity(I), 0.0, 1e-9);
  EXPECT_LT(law->firstPiola(I).norm(), 1e-9);
  const Matrix9d C = linearTensor(material.mu(), material.lambda());
  EXPECT_LT((law->firstPiolaDerivative(I) - C).norm(), 1e-12 * C.norm()) << law->name();
  EXPECT_LT((law->projectedFirstPiolaDerivative(I) - C).norm(), 1e-10 * C.norm()) << law->name();
}

TEST_P(LawTest, ProjectedTangentIsPsdUnderCompressionAndInversion) {
  std::mt19937 rng(3);
  Eigen::Matrix3d compressed = Eigen::Matrix3d::Identity();
  compressed.diagonal() << 0.4, 0.9, 0.5;
  for (const Eigen::Matrix3d& F : {compressed, randomF(rng, 0.3, true), randomF(rng, 0.5, false)}) {
    const Matrix9d A = law->projectedFirstPiolaDerivative(F);
    EXPECT_LT((A - A.transpose()).norm(), 1e-12 * A.norm());
    const Eigen::SelfAdjointEigenSolver<Matrix9d> eig(A);
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-10 * eig.eigenvalues().maxCoeff()) << law->name();
  }
  // The exact tangent is indefinite in strong compression (else the projection is untested).
  const Eigen::SelfAdjointEigenSolver<Matrix9d> exact(law->firstPiolaDerivative(compressed));
  EXPECT_LT(exact.eigenvalues().minCoeff(), 0.0) << law->name();
}

TEST_P(LawTest, ObjectiveUnderRotation) {
  std::mt19937 rng(5);
  const Eigen::Matrix3d F = randomF(rng, 0.3, false);
  const Eigen::Matrix3d Q =
      Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, 2, -1).normalized()).toRotationMatrix();
  EXPECT_NEAR(law->energyDensity(Q * F), law->energyDensity(F), 1e-10 * law->energyDensity(F));
  EXPECT_LT((law->firstPiola(Q * F) - Q * law->firstPiola(F)).norm(),
            1e-10 * law->firstPiola(F).norm());
}

INSTANTIATE_TEST_SUITE_P(AllLaws, LawTest, ::testing::Values(0, 1, 2));

TEST(SignedSvd, RotationsAndSignedSmallestValue) {
  std::mt19937 rng(1);
  for (bool inverted : {false, true}) {
    const Eigen::Matrix3d F = randomF(rng, 0.3, inverted);
    const SignedSvd svd = computeSignedSvd(F);
    EXPECT_NEAR(svd.U.determinant(), 1.0, 1e-12);
    EXPECT_NEAR(svd.V.determinant(), 1.0, 1e-12);
    EXPECT_LT((svd.U * svd.s.asDiagonal() * svd.V.transpose() - F).norm(), 1e-12);
    EXPECT_EQ(svd.s(2) < 0.0, inverted);
    EXPECT_GT(svd.s(1), 0.0);
  }
}

TEST(CorotationalLaw, SmallStretchEqualsLinearElasticity) {
  const Material m = test::testMaterial(0.3);
  const CorotationalLaw law(m);
  Eigen::Matrix3d eps;
  eps << 1.0, 0.3, -0.2, 0.3, -0.5, 0.1, -0.2, 0.1, 0.7;
  eps *= 1e-5;
  const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() + eps;  // symmetric: no rotation
  const double linear_psi =
      m.mu() * eps.squaredNorm() + 0.5 * m.lambda() * eps.trace() * eps.trace();
  const Eigen::Matrix3d linear_sigma =
      2 * m.mu() * eps + m.lambda() * eps.trace() * Eigen::Matrix3d::Identity();
  // The corotational law is exactly quadratic in the symmetric stretch.
  EXPECT_NEAR(law.energyDensity(F), linear_psi, 1e-9 * linear_psi);
  EXPECT_LT((law.firstPiola(F) - linear_sigma).norm(), 1e-9 * linear_sigma.norm());
}

TEST(CorotationalLaw, InvertedElementIsPushedBackOut) {
  const CorotationalLaw law(test::testMaterial(0.3));
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(2, 2) = -0.5;  // flattened through itself along z
  // Closest rotation is I (signed SVD), so the z stress pushes towards +1: P_zz < 0 pulls
  // -dpsi/dF_zz > 0.
  EXPECT_LT(law.firstPiola(F)(2, 2), 0.0);
  EXPECT_TRUE(std::isfinite(law.energyDensity(F)));
}

TEST(StVenantKirchhoffLaw, UniaxialStretchEnergyByHand) {
  const Material m = test::testMaterial(0.3);
  const StVenantKirchhoffLaw law(m);
  for (double l : {0.5, 0.9, 1.3, 2.0}) {
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    F(0, 0) = l;
    const double e = 0.5 * (l * l - 1.0);  // E_xx
    EXPECT_NEAR(law.energyDensity(F), (0.5 * m.lambda() + m.mu()) * e * e, 1e-12 * m.mu());
    EXPECT_NEAR(law.firstPiola(F)(0, 0), l * (m.lambda() + 2 * m.mu()) * e, 1e-12 * m.mu());
  }
}

TEST(StVenantKirchhoffLaw, UniaxialTractionFreeForceIdentity) {
  // F = diag(F_t, F_t, F_l) with F_t^2 = 1 - nu (F_l^2 - 1) makes S_xx = S_yy = 0 and
  // P_zz S0 = (E S0 / 2) F_l (F_l^2 - 1) (Chendeb eqs 3.68-3.79, simplified).
  for (double nu : {0.0, 0.3, 0.45}) {
    const Material m = Material::create(2.0e4, nu, 1000.0);
    const StVenantKirchhoffLaw law(m);
    const double S0 = 2.5e-3;  // 50 mm x 50 mm face [m^2]
    for (double Fl : {0.5, 0.76, 1.0 / std::sqrt(3.0), 1.2}) {
      const double Ft = std::sqrt(1.0 - nu * (Fl * Fl - 1.0));
      const Eigen::Matrix3d F = Eigen::Vector3d(Ft, Ft, Fl).asDiagonal();
      const Eigen::Matrix3d P = law.firstPiola(F);
      const double expected = 0.5 * m.young_modulus * S0 * Fl * (Fl * Fl - 1.0);
      EXPECT_NEAR(P(0, 0) / Ft, 0.0, 1e-12 * m.young_modulus);  // S_xx = P_xx / F_t
      EXPECT_NEAR(P(1, 1) / Ft, 0.0, 1e-12 * m.young_modulus);
      EXPECT_NEAR(P(2, 2) * S0, expected, 1e-12 * m.young_modulus * S0);
    }
  }
}

TEST(StableNeoHookeanLaw, FiniteForInvertedAndNearlyIncompressible) {
  const StableNeoHookeanLaw law(test::testMaterial(0.499));
  std::mt19937 rng(9);
  for (const Eigen::Matrix3d& F : {Eigen::Matrix3d(Eigen::Vector3d(1.0, 1.0, -0.3).asDiagonal()),
                                   Eigen::Matrix3d::Zero().eval(), randomF(rng, 0.4, true)}) {
    EXPECT_LE(F.determinant(), 0.0);
    EXPECT_TRUE(std::isfinite(law.energyDensity(F)));
    EXPECT_TRUE(law.firstPiola(F).allFinite());
    EXPECT_TRUE(law.firstPiolaDerivative(F).allFinite());
    EXPECT_TRUE(law.projectedFirstPiolaDerivative(F).allFinite());
  }
  // Inverted along z: the volume term pushes J back towards 1 (dpsi/dF_zz < 0 at F_zz < 0).
  EXPECT_LT(law.firstPiola(Eigen::Vector3d(1.0, 1.0, -0.3).asDiagonal())(2, 2), 0.0);
}

TEST(StableNeoHookeanLaw, ClosedFormProjectionEqualsTheClampedEigenvaluesOfTheExactTangent) {
  // Compressed, stretched, inverted, flat and nearly incompressible: the closed-form eigensystem
  // gives the projection a 9 x 9 eigensolver gives.
  std::mt19937 rng(13);
  for (const double nu : {0.3, 0.49}) {
    const Material m = test::testMaterial(nu);
    const StableNeoHookeanLaw law(m);
    std::vector<Eigen::Matrix3d> cases = {Eigen::Matrix3d::Identity(),
                                          Eigen::Vector3d(0.5, 0.6, 0.7).asDiagonal(),
                                          Eigen::Vector3d(1.6, 1.2, 0.9).asDiagonal(),
                                          Eigen::Vector3d(1.0, 1.0, -0.3).asDiagonal(),
                                          Eigen::Vector3d(1.0, 1.0, 0.0).asDiagonal(),
                                          Eigen::Vector3d(1.1, 1.1, 1.1).asDiagonal()};
    for (int trial = 0; trial < 20; ++trial) cases.push_back(randomF(rng, 0.5, trial % 2 == 1));
    for (const Eigen::Matrix3d& F : cases) {
      Matrix9d expected = law.firstPiolaDerivative(F);
      projectToPsd(expected);
      const Matrix9d projected = law.projectedFirstPiolaDerivative(F);
      EXPECT_LT((projected - expected).norm(), 1e-10 * (m.young_modulus + expected.norm()))
          << "nu " << nu << " F\n"
          << F;
    }
  }
}

TEST(HyperelasticLaw, InvalidMaterialThrows) {
  Material bad;
  bad.young_modulus = -1.0;
  bad.poisson_ratio = 0.3;
  bad.density = 1000.0;
  EXPECT_THROW(CorotationalLaw{bad}, std::invalid_argument);
  EXPECT_THROW(StVenantKirchhoffLaw{bad}, std::invalid_argument);
  EXPECT_THROW(StableNeoHookeanLaw{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
