#include "surgical_sim/core/tissue/mass_spring_model.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

TEST(MassSpringModel, SingleTetSpringStiffnessIsEVOverLSquared) {
  const Material m = test::testMaterial();
  const double size = 0.05;
  const MassSpringModel model(test::singleTet(size), m);
  ASSERT_EQ(model.springs().cols(), 6);
  const double V = size * size * size / 6.0;
  for (int j = 0; j < 6; ++j) {
    const double L = model.restLength()(j);
    EXPECT_NEAR(model.springStiffness()(j), m.young_modulus * V / (L * L), 1e-12 * m.young_modulus);
  }
  // Axis edges have L = size, the three face diagonals L = sqrt(2) size.
  EXPECT_NEAR(model.restLength().minCoeff(), size, 1e-15);
  EXPECT_NEAR(model.restLength().maxCoeff(), std::sqrt(2.0) * size, 1e-15);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(model.lumpedMass()(i), 1000.0 * V / 4.0, 1e-15);
  EXPECT_EQ(model.name(), "mass_spring");
}

TEST(MassSpringModel, SharedEdgeSumsVolumes) {
  const Material m = test::testMaterial();
  const MassSpringModel model(test::twoTets(), m);
  EXPECT_EQ(model.springs().cols(), 9);  // 6 + 6 - 3 shared edges of the common face
  for (int j = 0; j < model.springs().cols(); ++j) {
    const int a = model.springs()(0, j);
    const int b = model.springs()(1, j);
    const bool shared = a >= 1 && b <= 3;  // edges of face (1, 2, 3)
    const double volume = shared ? 1.0 / 6.0 + 1.0 / 3.0 : (a == 0 ? 1.0 / 6.0 : 1.0 / 3.0);
    const double L = model.restLength()(j);
    EXPECT_NEAR(model.springStiffness()(j), m.young_modulus * volume / (L * L), 1e-9)
        << a << "-" << b;
  }
}

TEST(MassSpringModel, UniformScalingEnergyByHand) {
  // x = s X: every spring has l = s L0, so W = sum 1/2 (E V / L0^2) (s - 1)^2 L0^2 = 3 E V (s-1)^2.
  const Material m = test::testMaterial();
  const MassSpringModel model(test::singleTet(), m);
  const double s = 1.3;
  const double V = 1.0 / 6.0;
  EXPECT_NEAR(model.energy(model.restPositions() * s),
              3.0 * m.young_modulus * V * (s - 1) * (s - 1), 1e-9);
}

TEST(MassSpringModel, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(21);
  for (const TetMesh& mesh : {test::singleTet(), test::cubeSixTets(1e-3)}) {
    const MassSpringModel model(mesh, test::testMaterial());
    const double size = mesh.nodes.maxCoeff();
    const Eigen::VectorXd x = test::perturbed(model.restPositions(), 0.2 * size, rng);
    test::expectForceIsMinusEnergyGradient(model, x, size);
    test::expectStiffnessIsMinusForceJacobian(model, x, size);
    test::expectApplyMatchesAssembled(model, x, rng);
  }
}

TEST(MassSpringModel, RigidModesRotationAndProjection) {
  const MassSpringModel model(test::cubeSixTets(), test::testMaterial());
  test::expectRigidModesInNullSpace(model);
  test::expectRotationIsForceFree(model);
  const Eigen::VectorXd x = test::compressedInverted(test::cubeSixTets());
  EXPECT_LT(test::exactMinEigenvalueRatio(model, x), -1e-6);
  test::expectProjectedIsPsd(model, x);
}

TEST(MassSpringModel, RejectsTet10AndBadMeshes) {
  const Material m = test::testMaterial();
  try {
    MassSpringModel model(test::toTet10(test::singleTet()), m);
    FAIL() << "tet10 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mass_spring"), std::string::npos) << e.what();
  }
  TetMesh inverted = test::singleTet();
  std::swap(inverted.elements(1, 0), inverted.elements(2, 0));
  EXPECT_THROW(MassSpringModel(inverted, m), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
