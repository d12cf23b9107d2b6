#include "surgical_sim/core/tissue/fe_model.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <string>

#include "surgical_sim/core/tissue/corotational_law.h"
#include "surgical_sim/core/tissue/st_venant_kirchhoff_law.h"
#include "surgical_sim/core/tissue/stable_neo_hookean_law.h"
#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

FeModel makeModel(const std::string& law, const TetMesh& mesh, double nu = 0.3) {
  const Material m = test::testMaterial(nu);
  return FeModel(mesh, m, test::makeLaw(law, m));
}

class FeModelTest : public ::testing::TestWithParam<test::LawCase> {
 protected:
  TetMesh mesh(double size = 1.0) const {
    const TetMesh cube = test::cubeSixTets(size);
    return GetParam().tet10 ? test::toTet10(cube) : cube;
  }
};

TEST_P(FeModelTest, ForceIsMinusEnergyGradient) {
  std::mt19937 rng(42);
  for (double size : {1.0, 1e-3}) {
    const FeModel model = makeModel(GetParam().law, mesh(size));
    const Eigen::VectorXd x = test::perturbed(model.restPositions(), 0.15 * size, rng);
    test::expectForceIsMinusEnergyGradient(model, x, size);
  }
}

TEST_P(FeModelTest, ExactStiffnessIsMinusForceJacobian) {
  std::mt19937 rng(43);
  for (double size : {1.0, 1e3}) {
    const FeModel model = makeModel(GetParam().law, mesh(size));
    const Eigen::VectorXd x = test::perturbed(model.restPositions(), 0.15 * size, rng);
    test::expectStiffnessIsMinusForceJacobian(model, x, size);
  }
}

TEST_P(FeModelTest, CompressedInvertedConfigurationDerivatives) {
  const FeModel model = makeModel(GetParam().law, mesh());
  std::mt19937 rng(44);
  const Eigen::VectorXd x = test::compressedInverted(test::cubeSixTets());
  Eigen::VectorXd xm = GetParam().tet10 ? model.restPositions() : x;
  if (GetParam().tet10) {
    // Move the corners as in the Tet4 configuration; mid-edge nodes follow the straight edges.
    const TetMesh m10 = mesh();
    for (int e = 0; e < m10.numElements(); ++e) {
      const int pairs[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
      for (int a = 0; a < 4; ++a)
        xm.segment<3>(3 * m10.elements(a, e)) = x.segment<3>(3 * m10.elements(a, e));
      for (int k = 0; k < 6; ++k) {
        xm.segment<3>(3 * m10.elements(4 + k, e)) =
            0.5 * (x.segment<3>(3 * m10.elements(pairs[k][0], e)) +
                   x.segment<3>(3 * m10.elements(pairs[k][1], e)));
      }
    }
  }
  xm = test::perturbed(xm, 0.02, rng);
  test::expectForceIsMinusEnergyGradient(model, xm, 1.0);
  test::expectStiffnessIsMinusForceJacobian(model, xm, 1.0);
  test::expectProjectedIsPsd(model, xm);
}

TEST_P(FeModelTest, ApplyStiffnessMatchesAssembled) {
  std::mt19937 rng(45);
  const FeModel model = makeModel(GetParam().law, mesh());
  test::expectApplyMatchesAssembled(model, test::perturbed(model.restPositions(), 0.2, rng), rng);
}

TEST_P(FeModelTest, RigidModesAndFiniteRotation) {
  const FeModel model = makeModel(GetParam().law, mesh());
  test::expectRigidModesInNullSpace(model);
  test::expectRotationIsForceFree(model);
}

TEST_P(FeModelTest, ProjectedStiffnessIsPsdUnderCompression) {
  const FeModel model = makeModel(GetParam().law, mesh());
  Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
  A.diagonal() << 0.9, 1.0, 0.35;
  const Eigen::VectorXd x = test::affine(model.restPositions(), A);
  EXPECT_LT(test::exactMinEigenvalueRatio(model, x), -1e-6);  // really indefinite
  test::expectProjectedIsPsd(model, x);
}

TEST_P(FeModelTest, MassAndBodyForce) {
  const FeModel model = makeModel(GetParam().law, mesh(2.0));
  const double total = 1000.0 * 8.0;  // rho * (2 m)^3
  const Eigen::VectorXd& m = model.lumpedMass();
  EXPECT_GT(m.minCoeff(), 0.0);
  EXPECT_NEAR(m.sum(), 3.0 * total, 1e-9 * total);
  const Eigen::Vector3d g(0.3, -9.81, 1.2);
  const Eigen::VectorXd f = model.bodyForce(g);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = 0; i < model.numNodes(); ++i) sum += f.segment<3>(3 * i);
  EXPECT_LT((sum - total * g).norm(), 1e-9 * total * g.norm());
}

TEST_P(FeModelTest, EnergyEqualForAffineDeformationOnTet4AndTet10) {
  Eigen::Matrix3d A;
  A << 1.2, 0.1, -0.05, 0.02, 0.85, 0.1, -0.1, 0.05, 1.1;
  const TetMesh cube = test::cubeSixTets();
  const FeModel tet4 = makeModel(GetParam().law, cube);
  const FeModel tet10 = makeModel(GetParam().law, test::toTet10(cube));
  const double e4 = tet4.energy(test::affine(tet4.restPositions(), A));
  const double e10 = tet10.energy(test::affine(tet10.restPositions(), A));
  EXPECT_GT(e4, 0.0);
  EXPECT_NEAR(e10, e4, 1e-12 * e4);
}

INSTANTIATE_TEST_SUITE_P(LawsAndElements, FeModelTest, test::allLawCases(), test::lawCaseName);

TEST(FeModel, NamesFollowTheLaw) {
  EXPECT_EQ(makeModel("corotational", test::singleTet()).name(), "corotational");
  EXPECT_EQ(makeModel("svk", test::singleTet()).name(), "svk");
  EXPECT_EQ(makeModel("neo_hookean", test::singleTet()).name(), "neo_hookean");
}

TEST(FeModel, SingleTetSvkUniaxialEnergyByHand) {
  // Unit right tet, V = 1/6, x = diag(l, 1, 1) X: W = V (lambda/2 + mu) ((l^2 - 1)/2)^2.
  const Material m = test::testMaterial(0.3);
  const FeModel model = makeModel("svk", test::singleTet());
  for (double l : {0.7, 1.1, 1.6}) {
    const Eigen::VectorXd x =
        test::affine(model.restPositions(), Eigen::Vector3d(l, 1.0, 1.0).asDiagonal());
    const double e = 0.5 * (l * l - 1.0);
    EXPECT_NEAR(model.energy(x), (0.5 * m.lambda() + m.mu()) * e * e / 6.0, 1e-12 * m.mu());
    // The two nodes with X = 0 carry no x-force by symmetry; node 1 (X = 1) carries
    // -V P_xx dN_1/dX = -V P_xx (dN_1/dX = (1, 0, 0)).
    const Eigen::VectorXd f = test::force(model, x);
    const double Pxx = l * (m.lambda() + 2.0 * m.mu()) * e;
    EXPECT_NEAR(f(3), -Pxx / 6.0, 1e-10 * m.mu());
  }
}

TEST(FeModel, CorotationalSmallStretchEqualsLinearElasticity) {
  const Material m = test::testMaterial(0.3);
  const FeModel model = makeModel("corotational", test::cubeSixTets());
  Eigen::Matrix3d eps;
  eps << 2.0, 0.5, 0.0, 0.5, -1.0, 0.3, 0.0, 0.3, 1.5;
  eps *= 1e-6;
  const Eigen::VectorXd u = test::affine(model.restPositions(), eps);
  const Eigen::VectorXd x = model.restPositions() + u;
  const double linear =
      1.0 * (m.mu() * eps.squaredNorm() + 0.5 * m.lambda() * eps.trace() * eps.trace());
  EXPECT_NEAR(model.energy(x), linear, 1e-6 * linear);
  // f = -K0 u with the rest stiffness.
  const Eigen::VectorXd Ku =
      test::denseStiffness(model, model.restPositions(), TangentMode::Exact) * u;
  EXPECT_LT((test::force(model, x) + Ku).norm(), 1e-6 * Ku.norm());
}

TEST(FeModel, Tet4LumpedMassIsQuarterOfElementMass) {
  const FeModel model = makeModel("corotational", test::singleTet(0.1));
  const double quarter = 1000.0 * (0.1 * 0.1 * 0.1 / 6.0) / 4.0;
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(model.lumpedMass()(i), quarter, 1e-15);
  const Eigen::VectorXd f = model.bodyForce(Eigen::Vector3d(0, 0, -9.81));
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(f(3 * i + 2), -9.81 * quarter, 1e-14);
}

TEST(FeModel, Tet10HrzMassAndConsistentBodyForceWeights) {
  const TetMesh mesh = test::toTet10(test::singleTet());
  const FeModel model = makeModel("svk", mesh);
  const double element_mass = 1000.0 / 6.0;
  const Eigen::VectorXd f = model.bodyForce(Eigen::Vector3d(0, 0, 1.0));
  // Affine Tet10: integral(N_corner) = -V/20, integral(N_mid) = V/5.
  for (int a = 0; a < 4; ++a) EXPECT_NEAR(f(3 * a + 2), -element_mass / 20.0, 1e-12);
  for (int a = 4; a < 10; ++a) EXPECT_NEAR(f(3 * a + 2), element_mass / 5.0, 1e-12);
  // HRZ: consistent diagonal corners 6V/420, mid-edges 32V/420, scaled to total mass.
  const double scale = element_mass / (4 * 6.0 + 6 * 32.0);
  for (int a = 0; a < 4; ++a) EXPECT_NEAR(model.lumpedMass()(3 * a), 6.0 * scale, 1e-12);
  for (int a = 4; a < 10; ++a) EXPECT_NEAR(model.lumpedMass()(3 * a), 32.0 * scale, 1e-12);
}

TEST(FeModel, InvalidInputsThrow) {
  const Material m = test::testMaterial();
  TetMesh inverted = test::twoTets();
  std::swap(inverted.elements(2, 1), inverted.elements(3, 1));
  try {
    FeModel model(inverted, m, std::make_unique<CorotationalLaw>(m));
    FAIL() << "inverted rest element accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("element 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("inverted"), std::string::npos) << e.what();
  }
  TetMesh flat = test::singleTet();
  flat.nodes(2, 3) = 0.0;  // apex in the base plane
  EXPECT_THROW(FeModel(flat, m, std::make_unique<CorotationalLaw>(m)), std::invalid_argument);
  // A Tet10 whose mid-edge node is dragged across the element: corners fine, det J < 0 inside.
  TetMesh bent = test::toTet10(test::singleTet());
  bent.nodes.col(bent.elements(7, 0)) = Eigen::Vector3d(0.6, 0.6, -0.5);
  try {
    FeModel model(bent, m, std::make_unique<StVenantKirchhoffLaw>(m));
    FAIL() << "tangled Tet10 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("element 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(FeModel(test::singleTet(), m, nullptr), std::invalid_argument);
  TetMesh out_of_range = test::singleTet();
  out_of_range.elements(3, 0) = 9;
  EXPECT_THROW(FeModel(out_of_range, m, std::make_unique<CorotationalLaw>(m)),
               std::invalid_argument);
  // Assembling into a matrix without the model's pattern is a programming error.
  const FeModel model = makeModel("svk", test::singleTet());
  Eigen::SparseMatrix<double> wrong(12, 12);
  EXPECT_THROW(model.assembleStiffness(model.restPositions(), TangentMode::Exact, wrong),
               std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
