#include "surgical_sim/core/tissue/efg_model.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <random>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/tissue/corotational_law.h"
#include "surgical_sim/core/tissue/point_stiffness.h"
#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

EfgOptions options(double spacing, EfgRotation rotation, int neighbours = 8) {
  EfgOptions o;
  o.spacing = spacing;
  o.rotation = rotation;
  o.neighbours = neighbours;
  return o;
}

// A slanted, irregular body (jittered lattice, 2 cells of 0.5 m) whose cells are cut by the
// surface: partial volumes, particles outside.
TetMesh irregularBody() {
  std::mt19937 rng(11);
  TetMesh mesh = test::jitteredLattice(2, 0.5, 0.08, rng);
  return mesh;
}

struct EfgCase {
  EfgRotation rotation;
  int neighbours;
};

class EfgModelTest : public ::testing::TestWithParam<EfgCase> {
 protected:
  EfgModel model(const TetMesh& mesh, double spacing) const {
    return EfgModel(mesh, test::testMaterial(0.3),
                    options(spacing, GetParam().rotation, GetParam().neighbours));
  }
};

std::string caseName(const ::testing::TestParamInfo<EfgCase>& info) {
  return std::string(enumName(kEfgRotationNames, info.param.rotation)) + "_" +
         std::to_string(info.param.neighbours);
}

INSTANTIATE_TEST_SUITE_P(Efg, EfgModelTest,
                         ::testing::Values(EfgCase{EfgRotation::Polar, 8},
                                           EfgCase{EfgRotation::ShapeMatching, 8},
                                           EfgCase{EfgRotation::Polar, 12},
                                           EfgCase{EfgRotation::ShapeMatching, 16}),
                         caseName);

TEST_P(EfgModelTest, LumpedMassSumsToRhoVolumeAndBodyForceToWeight) {
  const TetMesh box = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.5, 0.5),
                              Eigen::Vector3i(2, 1, 1), ElementType::Tet4);
  const EfgModel aligned = model(box, 0.125);
  EXPECT_NEAR(aligned.lumpedMass().sum() / 3.0, 1000.0 * 0.25, 1e-9);
  const EfgModel m = model(irregularBody(), 0.15);
  const double total = 1000.0 * m.grid().volumes.sum();
  EXPECT_NEAR(m.lumpedMass().sum() / 3.0, total, 1e-10 * total);
  EXPECT_GT(m.lumpedMass().minCoeff(), 0.0);
  const Eigen::Vector3d g(0.0, -9.81, 1.0);
  const Eigen::VectorXd f = m.bodyForce(g);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = 0; i < m.numNodes(); ++i) sum += f.segment<3>(3 * i);
  EXPECT_LT((sum - total * g).norm(), 1e-10 * total * g.norm());
}

TEST_P(EfgModelTest, AffineDeformationGivesExactUniformStrain) {
  const EfgModel m = model(irregularBody(), 0.15);
  Eigen::Matrix3d A;
  A << 1.05, 0.02, 0.0, -0.01, 0.97, 0.03, 0.0, 0.01, 1.02;
  const Eigen::VectorXd x = test::affine(m.restPositions(), A, Eigen::Vector3d(0.1, 0.2, -0.3));
  // Linear completeness: every IP sees F = A, so E = sum V psi(A). Shape matching takes the
  // rotation of A A_qq (A_qq: the IP's weighted particle moments), close to but not exactly the
  // polar rotation of A.
  const CorotationalLaw law(test::testMaterial(0.3));
  const double tol = GetParam().rotation == EfgRotation::Polar ? 1e-12 : 1e-3;
  EXPECT_NEAR(m.energy(x), m.grid().volumes.sum() * law.energyDensity(A), tol * m.energy(x));
}

TEST_P(EfgModelTest, RigidMotionsAreForceFree) {
  const EfgModel m = model(irregularBody(), 0.15);
  test::expectRotationIsForceFree(m);
  test::expectRigidModesInNullSpace(m);
}

TEST_P(EfgModelTest, StiffnessMatchesForceDifferencesAtRigidRotation) {
  const EfgModel m = model(irregularBody(), 0.3);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
  test::expectStiffnessIsMinusForceJacobian(m, test::affine(m.restPositions(), R), 1.0, 1e-6);
}

TEST_P(EfgModelTest, ApplyAndFusedMatchAssembled) {
  const EfgModel m = model(irregularBody(), 0.3);
  std::mt19937 rng(2);
  const Eigen::VectorXd x = test::perturbed(m.restPositions(), 0.02, rng);
  test::expectApplyMatchesAssembled(m, x, rng);
  for (TangentMode mode : {TangentMode::Exact, TangentMode::ProjectedSpd}) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
    Eigen::SparseMatrix<double> K = m.stiffnessPattern();
    m.addInternalForceAndStiffness(x, mode, f, K);
    EXPECT_LT(test::relativeError(f, test::force(m, x)), 1e-13);
    EXPECT_LT(test::relativeError(Eigen::MatrixXd(K), test::denseStiffness(m, x, mode)), 1e-13);
    // With the energy from the same rotations: the same force, stiffness and energy.
    Eigen::VectorXd f_with_energy = Eigen::VectorXd::Zero(x.size());
    Eigen::SparseMatrix<double> K_with_energy = m.stiffnessPattern();
    const double energy =
        m.addInternalForceStiffnessAndEnergy(x, mode, f_with_energy, K_with_energy);
    EXPECT_EQ(energy, m.energy(x));
    EXPECT_LT(test::relativeError(f_with_energy, f), 1e-15);
    EXPECT_LT(test::relativeError(Eigen::MatrixXd(K_with_energy), Eigen::MatrixXd(K)), 1e-15);
  }
  test::expectProjectedIsPsd(m, x);
}

TEST_P(EfgModelTest, ScaleRobustMillimetresVersusMetres) {
  const TetMesh body = irregularBody();
  TetMesh body_mm = body;
  body_mm.nodes *= 1e-3;
  const EfgModel m = model(body, 0.3);
  const EfgModel mm = model(body_mm, 3e-4);
  ASSERT_EQ(m.numNodes(), mm.numNodes());
  std::mt19937 rng(4);
  const Eigen::VectorXd x = test::perturbed(m.restPositions(), 0.03, rng);
  const Eigen::VectorXd x_mm = 1e-3 * x;
  // Same strain: force ~ E L^2, stiffness ~ E L, mass ~ rho L^3.
  EXPECT_LT(test::relativeError(1e6 * test::force(mm, x_mm), test::force(m, x)), 1e-9);
  EXPECT_LT(test::relativeError(1e3 * test::denseStiffness(mm, x_mm, TangentMode::Exact),
                                test::denseStiffness(m, x, TangentMode::Exact)),
            1e-9);
  EXPECT_LT(test::relativeError(1e9 * mm.lumpedMass(), m.lumpedMass()), 1e-9);
}

TEST(EfgModel, PolarForceIsEnergyGradientAndStiffnessItsExactHessian) {
  const EfgModel m(irregularBody(), test::testMaterial(0.3), options(0.3, EfgRotation::Polar));
  std::mt19937 rng(6);
  const Eigen::VectorXd x = test::perturbed(m.restPositions(), 0.05, rng);
  test::expectForceIsMinusEnergyGradient(m, x, 1.0);
  test::expectStiffnessIsMinusForceJacobian(m, x, 1.0);
}

TEST(EfgModel, ProjectedPolarTangentIsTheSumOfPointTangents) {
  // The projected polar tangent, summed per group of IPs that share their particles, is the sum
  // over the IPs of w G^T (dP/dF) G with the law's fixed-R tangent, built point by point.
  const Material material = test::testMaterial(0.3);
  const CorotationalLaw law(material);
  for (int neighbours : {8, 12}) {
    const EfgModel m(irregularBody(), material, options(0.15, EfgRotation::Polar, neighbours));
    std::mt19937 rng(12);
    const Eigen::VectorXd x =
        test::affine(test::perturbed(m.restPositions(), 0.05, rng),
                     Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitY()).toRotationMatrix());
    const Eigen::MatrixXi& nb = m.grid().neighbours;
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(x.size(), x.size());
    for (int e = 0; e < nb.cols(); ++e) {
      Eigen::Matrix3Xd xe(3, neighbours);
      for (int a = 0; a < neighbours; ++a) xe.col(a) = x.segment<3>(3 * nb(a, e));
      const Eigen::MatrixXd G = m.shapeGradients(e);
      Eigen::MatrixXd Ke = Eigen::MatrixXd::Zero(3 * neighbours, 3 * neighbours);
      addPointStiffness(law.projectedFirstPiolaDerivative(xe * G), G, m.grid().volumes(e), Ke);
      for (int a = 0; a < neighbours; ++a)
        for (int b = 0; b < neighbours; ++b)
          expected.block<3, 3>(3 * nb(a, e), 3 * nb(b, e)) += Ke.block<3, 3>(3 * a, 3 * b);
    }
    EXPECT_LT(test::relativeError(test::denseStiffness(m, x, TangentMode::ProjectedSpd), expected),
              1e-12)
        << neighbours;
  }
}

TEST(EfgModel, ShapeMatchingTangentErrorIsBoundedByTheStrain) {
  // The fixed-R tangent omits dR/dx, a term proportional to the stress: its relative error
  // against the force differences shrinks linearly with the deformation amplitude.
  const EfgModel m(irregularBody(), test::testMaterial(0.3),
                   options(0.3, EfgRotation::ShapeMatching));
  const Eigen::VectorXd& X = m.restPositions();
  std::mt19937 rng(8);
  const Eigen::VectorXd direction = test::perturbed(Eigen::VectorXd::Zero(X.size()), 1.0, rng);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  double previous = INFINITY;
  for (double amplitude : {0.04, 0.01, 0.0025}) {
    const Eigen::VectorXd x = test::affine(X + amplitude * direction, R);
    const double h = 1e-6;
    Eigen::MatrixXd fd(X.size(), X.size());
    Eigen::VectorXd xp = x;
    for (Eigen::Index j = 0; j < X.size(); ++j) {
      xp(j) = x(j) + h;
      const Eigen::VectorXd fp = test::force(m, xp);
      xp(j) = x(j) - h;
      fd.col(j) = -(fp - test::force(m, xp)) / (2.0 * h);
      xp(j) = x(j);
    }
    const double error = test::relativeError(test::denseStiffness(m, x, TangentMode::Exact), fd);
    EXPECT_LT(error, 2.0 * amplitude) << amplitude;
    EXPECT_LT(error, previous);
    previous = error;
  }
}

TEST(EfgModel, InterpolationMovesMeshNodesWithTheParticles) {
  const TetMesh body = irregularBody();
  const EfgModel m(body, test::testMaterial(0.3), options(0.15, EfgRotation::Polar));
  const Eigen::SparseMatrix<double> W = m.interpolation(body.nodes);
  ASSERT_EQ(W.rows(), body.numNodes());
  ASSERT_EQ(W.cols(), m.numNodes());
  EXPECT_LT((W * Eigen::VectorXd::Ones(m.numNodes()) - Eigen::VectorXd::Ones(W.rows()))
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
  // An affine motion of the particles moves every mesh node by the same map.
  Eigen::Matrix3d A;
  A << 1.1, 0.2, 0.0, -0.1, 0.9, 0.3, 0.05, 0.0, 1.2;
  const Eigen::Vector3d t(0.3, -0.2, 0.1);
  const Eigen::VectorXd x = test::affine(m.restPositions(), A, t);
  const Eigen::Map<const Eigen::Matrix3Xd> particles(x.data(), 3, m.numNodes());
  const Eigen::Matrix3Xd moved = (W * particles.transpose()).transpose();
  const Eigen::Matrix3Xd expected = (A * body.nodes).colwise() + t;
  EXPECT_LT((moved - expected).cwiseAbs().maxCoeff(), 1e-12);
  // At an IP, the weights are the IP's own shape functions.
  const Eigen::SparseMatrix<double> at_ip =
      m.interpolation(m.grid().integration_points.leftCols(1));
  for (int a = 0; a < m.options().neighbours; ++a)
    EXPECT_NEAR(at_ip.coeff(0, m.grid().neighbours(a, 0)), m.shapeValues(0)(a), 1e-12);
}

TEST(EfgModel, RejectsInvalidMaterialAndOptions) {
  const TetMesh body = irregularBody();
  Material bad = test::testMaterial();
  bad.density = -1.0;
  EXPECT_THROW(EfgModel(body, bad, options(0.3, EfgRotation::Polar)), std::invalid_argument);
  EXPECT_THROW(EfgModel(body, test::testMaterial(), options(0.0, EfgRotation::Polar)),
               std::invalid_argument);
  EXPECT_THROW(EfgModel(body, test::testMaterial(), options(0.3, EfgRotation::Polar, 20)),
               std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
