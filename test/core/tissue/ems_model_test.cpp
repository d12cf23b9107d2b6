#include "surgical_sim/core/tissue/ems_model.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <string>

#include "surgical_sim/core/tissue/fe_model.h"
#include "surgical_sim/core/tissue/st_venant_kirchhoff_law.h"
#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

FeModel svkModel(const TetMesh& mesh, const Material& m) {
  return FeModel(mesh, m, std::make_unique<StVenantKirchhoffLaw>(m));
}

TetMesh randomTet(std::mt19937& rng) {
  TetMesh mesh = test::singleTet();
  mesh.nodes = test::perturbed(test::flatten(mesh.nodes), 0.3, rng).reshaped(3, 4);
  test::orientTet4(mesh);
  return mesh;
}

TEST(EmsModel, EqualsSvkFiniteElementsToRoundOff) {
  std::mt19937 rng(31);
  const Material m = test::testMaterial(0.35);
  std::vector<TetMesh> meshes = {test::cubeSixTets(), test::twoTets(), test::cubeSixTets(1e-3)};
  for (int i = 0; i < 5; ++i) meshes.push_back(randomTet(rng));
  for (const TetMesh& mesh : meshes) {
    const EmsModel ems(mesh, m);
    const FeModel svk = svkModel(mesh, m);
    const double size = mesh.nodes.cwiseAbs().maxCoeff();
    for (int trial = 0; trial < 3; ++trial) {
      const Eigen::VectorXd x = test::perturbed(ems.restPositions(), 0.3 * size, rng);
      const Eigen::VectorXd f_svk = test::force(svk, x);
      EXPECT_LT(test::relativeError(test::force(ems, x), f_svk), 1e-12);
      EXPECT_NEAR(ems.energy(x), svk.energy(x), 1e-12 * svk.energy(x));
      for (TangentMode mode : {TangentMode::Exact}) {
        EXPECT_LT(test::relativeError(test::denseStiffness(ems, x, mode),
                                      test::denseStiffness(svk, x, mode)),
                  1e-11);
      }
    }
    EXPECT_TRUE(ems.lumpedMass().isApprox(svk.lumpedMass(), 1e-14));
  }
}

TEST(EmsModel, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(32);
  const EmsModel model(test::cubeSixTets(), test::testMaterial());
  const Eigen::VectorXd x = test::perturbed(model.restPositions(), 0.2, rng);
  test::expectForceIsMinusEnergyGradient(model, x, 1.0);
  test::expectStiffnessIsMinusForceJacobian(model, x, 1.0);
  test::expectApplyMatchesAssembled(model, x, rng);
}

TEST(EmsModel, RigidModesRotationAndProjection) {
  const EmsModel model(test::cubeSixTets(), test::testMaterial());
  test::expectRigidModesInNullSpace(model);
  test::expectRotationIsForceFree(model);
  Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
  A.diagonal() << 0.9, 1.0, 0.35;
  const Eigen::VectorXd compressed = test::affine(model.restPositions(), A);
  EXPECT_LT(test::exactMinEigenvalueRatio(model, compressed), -1e-6);
  test::expectProjectedIsPsd(model, compressed);
  test::expectProjectedIsPsd(model, test::compressedInverted(test::cubeSixTets()));
}

TEST(EmsModel, SingleTetUniaxialEnergyByHand) {
  const Material m = test::testMaterial(0.3);
  const EmsModel model(test::singleTet(), m);
  EXPECT_EQ(model.name(), "ems");
  const double l = 1.25;
  const double e = 0.5 * (l * l - 1.0);
  const Eigen::VectorXd x =
      test::affine(model.restPositions(), Eigen::Vector3d(l, 1.0, 1.0).asDiagonal());
  EXPECT_NEAR(model.energy(x), (0.5 * m.lambda() + m.mu()) * e * e / 6.0, 1e-12 * m.mu());
}

TEST(EmsModel, RejectsTet10) {
  try {
    EmsModel model(test::toTet10(test::singleTet()), test::testMaterial());
    FAIL() << "tet10 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ems"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace surgical_sim::core
