#include "surgical_sim/core/tissue/efg_model.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <memory>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/solve/pcg_solver.h"
#include "surgical_sim/core/solve/system_matrix.h"
#include "surgical_sim/core/tissue/corotational_law.h"
#include "surgical_sim/core/tissue/point_stiffness.h"
#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

EfgOptions options(double spacing, EfgRotation rotation, int neighbours = 8,
                   double stabilization = EfgOptions().stabilization) {
  EfgOptions o;
  o.spacing = spacing;
  o.rotation = rotation;
  o.neighbours = neighbours;
  o.stabilization = stabilization;
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
  // over the IPs of w G^T (dP/dF) G with the law's fixed-R tangent, built point by point
  // (without the stabilisation, whose energy the next tests check).
  const Material material = test::testMaterial(0.3);
  const CorotationalLaw law(material);
  for (int neighbours : {8, 12}) {
    const EfgModel m(irregularBody(), material, options(0.15, EfgRotation::Polar, neighbours, 0.0));
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

// IP 0 gains the nearest particle outside its set (one more, at most 16; with detours), IP 1 keeps
// 5 of its corners, and 10 % of IP 0's volume moves to IP 1.
std::vector<EfgNeighbourhood> replacedNeighbourhoods(const EfgModel& m) {
  const Eigen::Matrix3Xd& X = m.grid().particles;
  EfgNeighbourhood a;
  a.ip = 0;
  a.particles = m.ipParticles(0);
  const Eigen::Vector3d x0 = m.grid().integration_points.col(0);
  int extra = -1;
  double best = INFINITY;
  for (int p = 0; p < X.cols(); ++p) {
    const double d = (X.col(p) - x0).norm();
    if (d < best && std::find(a.particles.begin(), a.particles.end(), p) == a.particles.end()) {
      best = d;
      extra = p;
    }
  }
  if (a.particles.size() == EfgOptions::kMaxNeighbours) a.particles.pop_back();
  a.particles.push_back(extra);
  for (size_t i = 0; i < a.particles.size(); ++i)
    a.distances.push_back((X.col(a.particles[i]) - x0).norm() * (i % 2 == 0 ? 1.0 : 1.3));
  a.volume = 0.9 * m.grid().volumes(0);
  EfgNeighbourhood b;
  b.ip = 1;
  b.particles.assign(m.ipParticles(1).begin(), m.ipParticles(1).begin() + 5);
  b.volume = m.grid().volumes(1) + 0.1 * m.grid().volumes(0);
  return {a, b};
}

TEST_P(EfgModelTest, ReplacedNeighbourhoodsStayCompleteConservativeAndConsistent) {
  const EfgModel before = model(irregularBody(), 0.15);
  EfgModel m = before;
  m.setNeighbourhoods(replacedNeighbourhoods(m));
  EXPECT_EQ(m.ipParticles(0).size(),
            std::min<size_t>(m.options().neighbours + 1, EfgOptions::kMaxNeighbours));
  EXPECT_EQ(m.ipParticles(1).size(), 5u);
  EXPECT_NEAR(m.lumpedMass().sum(), before.lumpedMass().sum(), 1e-12 * before.lumpedMass().sum());
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  EXPECT_NEAR(m.bodyForce(g).sum(), before.bodyForce(g).sum(), 1e-12 * before.bodyForce(g).norm());
  for (int e = 0; e < 2; ++e) {
    const std::vector<int>& p = m.ipParticles(e);
    const Eigen::VectorXd phi = m.shapeValues(e);
    const Eigen::MatrixXd G = m.shapeGradients(e);
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
    for (size_t a = 0; a < p.size(); ++a) {
      x += phi(static_cast<Eigen::Index>(a)) * m.grid().particles.col(p[a]);
      F += m.grid().particles.col(p[a]) * G.row(static_cast<Eigen::Index>(a));
    }
    EXPECT_NEAR(phi.sum(), 1.0, 1e-13);
    EXPECT_LT((x - m.grid().integration_points.col(e)).norm(), 1e-13);
    EXPECT_LT((F - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    // Surface points use the same set and detours: sum 1, linear fields reproduced.
    std::vector<int> particles;
    std::vector<double> w;
    const Eigen::Vector3d X =
        m.grid().integration_points.col(e) + Eigen::Vector3d(0.02, -0.03, 0.01);
    m.pointWeights(e, X, particles, w);
    EXPECT_EQ(particles, p);
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    for (size_t a = 0; a < p.size(); ++a) y += w[a] * m.grid().particles.col(p[a]);
    EXPECT_LT((y - X).norm(), 1e-13);
    // A point beyond every particle's kernel (a surface vertex remapped to an IP across a cut)
    // still rests where it is, not at the IP.
    const Eigen::Vector3d far = m.grid().integration_points.col(e) +
                                3.0 * m.support(e) * Eigen::Vector3d(2.0, -3.0, 1.0).normalized();
    for (const int a : p) ASSERT_GT((m.grid().particles.col(a) - far).norm(), m.support(e));
    m.pointWeights(e, far, particles, w);
    y.setZero();
    for (size_t a = 0; a < p.size(); ++a) y += w[a] * m.grid().particles.col(p[a]);
    EXPECT_LT((y - far).norm(), 1e-12 * far.norm());
    EXPECT_NEAR(std::accumulate(w.begin(), w.end(), 0.0), 1.0, 1e-12);
  }
  // Gradients are the exact derivatives of the detoured functions.
  const Eigen::Vector3d x0 = m.grid().integration_points.col(0);
  const double h = 1e-6;
  std::vector<int> particles;
  std::vector<double> wp, wm;
  for (int c = 0; c < 3; ++c) {
    m.pointWeights(0, x0 + h * Eigen::Vector3d::Unit(c), particles, wp);
    m.pointWeights(0, x0 - h * Eigen::Vector3d::Unit(c), particles, wm);
    for (size_t a = 0; a < wp.size(); ++a)
      EXPECT_NEAR((wp[a] - wm[a]) / (2 * h), m.shapeGradients(0)(static_cast<Eigen::Index>(a), c),
                  1e-6);
  }
  test::expectRotationIsForceFree(m);
  test::expectRigidModesInNullSpace(m);
  std::mt19937 rng(3);
  const Eigen::VectorXd x = test::perturbed(m.restPositions(), 0.02, rng);
  test::expectApplyMatchesAssembled(m, x, rng);
  if (m.options().rotation == EfgRotation::Polar) {
    test::expectForceIsMinusEnergyGradient(m, x, 1.0);
    test::expectStiffnessIsMinusForceJacobian(m, x, 1.0);
  }
}

// The stabilisation energy from its definition: c mu V_e sum_a |d_a|^2 / sum_a |X_a - X_e|^2 per
// IP, d_a = x_a - (sum_b phi_b x_b + F_e (X_a - X_e)) the particle's distance from the IP's affine
// prediction, F_e = sum_b x_b grad phi_b^T.
double stabilizationEnergy(const EfgModel& m, const Eigen::VectorXd& x) {
  double energy = 0.0;
  for (int e = 0; e < m.numIntegrationPoints(); ++e) {
    const std::vector<int>& p = m.ipParticles(e);
    const Eigen::VectorXd phi = m.shapeValues(e);
    const Eigen::MatrixXd G = m.shapeGradients(e);
    const Eigen::Vector3d X_e = m.grid().integration_points.col(e);
    Eigen::Vector3d x_e = Eigen::Vector3d::Zero();
    Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
    for (size_t a = 0; a < p.size(); ++a) {
      x_e += phi(static_cast<Eigen::Index>(a)) * x.segment<3>(3 * p[a]);
      F += x.segment<3>(3 * p[a]) * G.row(static_cast<Eigen::Index>(a));
    }
    double deviation = 0.0;
    double spread = 0.0;
    for (int a : p) {
      const Eigen::Vector3d rel = m.grid().particles.col(a) - X_e;
      deviation += (x.segment<3>(3 * a) - x_e - F * rel).squaredNorm();
      spread += rel.squaredNorm();
    }
    energy += m.options().stabilization * test::testMaterial(0.3).mu() * m.grid().volumes(e) *
              deviation / spread;
  }
  return energy;
}

TEST_P(EfgModelTest, StabilizationAddsTheNonAffineDistanceEnergy) {
  EfgOptions plain = options(0.15, GetParam().rotation, GetParam().neighbours, 0.0);
  EfgOptions stabilized = plain;
  stabilized.stabilization = 0.3;
  EfgModel m0(irregularBody(), test::testMaterial(0.3), plain);
  EfgModel m(irregularBody(), test::testMaterial(0.3), stabilized);
  std::mt19937 rng(21);
  for (int pass = 0; pass < 2; ++pass) {
    const Eigen::VectorXd x = test::perturbed(m.restPositions(), 0.03, rng);
    const double expected = stabilizationEnergy(m, x);
    EXPECT_GT(expected, 1e-3 * m0.energy(x));
    EXPECT_NEAR(m.energy(x) - m0.energy(x), expected, 1e-11 * m.energy(x)) << pass;
    // Affine motions (stretch, shear, rotation) add nothing.
    Eigen::Matrix3d A;
    A << 1.2, 0.1, -0.05, 0.0, 0.9, 0.2, 0.1, 0.0, 1.1;
    const Eigen::VectorXd affine = test::affine(m.restPositions(), A, Eigen::Vector3d(1, 2, 3));
    EXPECT_LT(stabilizationEnergy(m, affine), 1e-20 * m.energy(affine));
    EXPECT_NEAR(m.energy(affine), m0.energy(affine), 1e-11 * m0.energy(affine));
    // After replaced neighbourhoods the changed IPs' groups carry their new matrices.
    m.setNeighbourhoods(replacedNeighbourhoods(m));
    m0.setNeighbourhoods(replacedNeighbourhoods(m0));
  }
  if (GetParam().rotation == EfgRotation::Polar)
    test::expectForceIsMinusEnergyGradient(m, test::perturbed(m.restPositions(), 0.02, rng), 1.0);
}

TEST(EfgModel, StabilizationLeavesOnlyTheRigidZeroEnergyModes) {
  // One 2 cm tet on cells of 1.5 mm: DOF cells at its sharp corners and edges keep a single IP
  // whose far particles no other IP uses. Four or more particles of one IP admit motions that
  // leave F unchanged (their gradients are linearly dependent): zero-energy modes beyond the 6
  // rigid ones, which the stabilisation removes.
  TetMesh tet;
  tet.nodes.resize(3, 4);
  tet.nodes << 0, 0.02, 0, 0, 0, 0, 0.02, 0, 0, 0, 0, 0.02;
  tet.elements.resize(4, 1);
  tet.elements << 0, 1, 2, 3;
  const auto zeroModes = [&](double stabilization) {
    const EfgModel m(tet, test::testMaterial(0.3),
                     options(0.0015, EfgRotation::Polar, 8, stabilization));
    const Eigen::MatrixXd K = test::denseStiffness(m, m.restPositions(), TangentMode::Exact);
    const Eigen::VectorXd eigenvalues =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues();
    return (eigenvalues.array() < 1e-12 * eigenvalues.maxCoeff()).count();
  };
  EXPECT_GT(zeroModes(0.0), 6);
  EXPECT_EQ(zeroModes(0.01), 6);
  EXPECT_EQ(zeroModes(0.1), 6);
}

// The current neighbourhood of IP e (particles, Euclidean distances, volume).
EfgNeighbourhood neighbourhoodOf(const EfgModel& m, int e) {
  EfgNeighbourhood n;
  n.ip = e;
  n.particles = m.ipParticles(e);
  n.volume = m.grid().volumes(e);
  return n;
}

// Changes applied one batch at a time (groups created, joined, emptied and removed) leave the
// same model as the net change in one batch, on a pattern that only grows: it is kept while no
// new particle set couples an uncoupled pair, and the entries it keeps beyond the net change's
// pattern stay zero.
TEST_P(EfgModelTest, BatchesOfChangesMatchTheirNetChangeOnAKeptPattern) {
  const EfgModel before = model(irregularBody(), 0.15);
  EfgModel stepwise = before;
  stepwise.setNeighbourhoods(replacedNeighbourhoods(before));
  const Eigen::SparseMatrix<double> grown = stepwise.stiffnessPattern();
  // IP 0's extra particle is a new coupling unless IP 0 already had the most particles.
  EXPECT_EQ(samePattern(grown, before.stiffnessPattern()),
            before.ipParticles(0).size() == EfgOptions::kMaxNeighbours);
  // IP 1 back to its set; IP 2 into the group of the last IP (another cell), with its volume.
  const int last = before.numIntegrationPoints() - 1;
  ASSERT_NE(before.ipParticles(2), before.ipParticles(last));
  EfgNeighbourhood moved = neighbourhoodOf(before, last);
  moved.ip = 2;
  moved.volume = before.grid().volumes(2);
  stepwise.setNeighbourhoods({neighbourhoodOf(before, 1), moved});
  EXPECT_TRUE(samePattern(grown, stepwise.stiffnessPattern()));
  stepwise.setNeighbourhoods({neighbourhoodOf(before, 0)});
  EXPECT_TRUE(samePattern(grown, stepwise.stiffnessPattern()));

  EfgModel net = before;
  net.setNeighbourhoods({moved});
  std::mt19937 rng(5);
  const Eigen::VectorXd x = test::perturbed(before.restPositions(), 0.05, rng);
  Eigen::VectorXd fs = Eigen::VectorXd::Zero(x.size()), fn = fs;
  Eigen::SparseMatrix<double> Ks = stepwise.stiffnessPattern(), Kn = net.stiffnessPattern();
  const double es = stepwise.addInternalForceStiffnessAndEnergy(x, TangentMode::Exact, fs, Ks);
  const double en = net.addInternalForceStiffnessAndEnergy(x, TangentMode::Exact, fn, Kn);
  EXPECT_NEAR(es, en, 1e-12 * std::abs(en));
  EXPECT_LT((fs - fn).norm(), 1e-12 * fn.norm());
  EXPECT_LT(Eigen::MatrixXd(Ks - Kn).norm(), 1e-12 * Eigen::MatrixXd(Kn).norm());
  EXPECT_LT((stepwise.lumpedMass() - net.lumpedMass()).norm(), 1e-14 * net.lumpedMass().norm());
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  EXPECT_LT((stepwise.bodyForce(g) - net.bodyForce(g)).norm(), 1e-14 * net.bodyForce(g).norm());
  test::expectApplyMatchesAssembled(stepwise, x, rng);
}

// A cut changes the model in place (new neighbourhoods, pattern and masses): an integrator told
// modelChanged() keeps its warped Cholesky factor (no new analysis: a local correction on the
// changed unknowns) and its buffers, and its steps match those of a direct solver re-set by
// reset(); it must not reuse the force and stiffness it evaluated with the old model.
TEST(EfgModel, StepsAfterAnInPlaceChangeMatchAReSetIntegrator) {
  EfgModel m(irregularBody(), test::testMaterial(0.3), options(0.15, EfgRotation::ShapeMatching));
  DynamicsProblem problem;
  problem.model = &m;
  const Eigen::VectorXd& X = m.restPositions();
  const double bottom = m.grid().particles.row(2).minCoeff();
  for (int p = 0; p < m.numNodes(); ++p) {
    if (m.grid().particles(2, p) > bottom + 0.1) continue;
    for (int i = 0; i < 3; ++i) problem.dirichlet.dofs.push_back(3 * p + i);
  }
  problem.dirichlet.positions.resize(static_cast<Eigen::Index>(problem.dirichlet.dofs.size()));
  for (size_t k = 0; k < problem.dirichlet.dofs.size(); ++k)
    problem.dirichlet.positions[static_cast<Eigen::Index>(k)] = X[problem.dirichlet.dofs[k]];
  const Eigen::Vector3d g(3.0, 0.0, -9.81);
  problem.external_force = 50.0 * m.bodyForce(g);
  PcgSettings pcg;
  pcg.relative_tolerance = 1e-12;
  auto warped = std::make_unique<PcgSolver>(PcgPreconditioner::CholeskyWarped, pcg);
  const PcgSolver& solver = *warped;
  const auto kept = makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {}, std::move(warped));
  const auto reference = makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {},
                                        makeLinearSolver(SolverKind::Cholmod, {}));
  SimulationState a{X, Eigen::VectorXd::Zero(X.size()), 0.0};
  SimulationState b = a;
  const double dt = 0.01;
  const auto stepBoth = [&] {
    ASSERT_EQ(kept->step(problem, dt, a).status, StepStatus::Ok);
    ASSERT_EQ(reference->step(problem, dt, b).status, StepStatus::Ok);
    EXPECT_LT((a.x - b.x).norm(), 1e-8 * (b.x - X).norm());
    EXPECT_LT((a.v - b.v).norm(), 1e-8 * b.v.norm());
  };
  for (int k = 0; k < 3; ++k) stepBoth();
  const Eigen::SparseMatrix<double> pattern = m.stiffnessPattern();
  m.setNeighbourhoods(replacedNeighbourhoods(m));
  ASSERT_FALSE(samePattern(pattern, m.stiffnessPattern()));
  problem.external_force = 50.0 * m.bodyForce(g);
  kept->modelChanged();
  reference->reset();
  for (int k = 0; k < 3; ++k) stepBoth();
  EXPECT_EQ(solver.choleskyAnalyses(), 1);
  EXPECT_EQ(solver.choleskyFactorizations(), 1);
}

TEST(EfgModel, BadNeighbourhoodsAreNamedAndLeaveTheModelUnchanged) {
  EfgModel m(irregularBody(), test::testMaterial(0.3), options(0.15, EfgRotation::Polar));
  const Eigen::VectorXd mass = m.lumpedMass();
  const auto message = [&](std::vector<EfgNeighbourhood> changes) {
    try {
      m.setNeighbourhoods(changes);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::vector<EfgNeighbourhood> good = replacedNeighbourhoods(m);
  auto c = good;
  c[1].particles.resize(17, 0);
  EXPECT_NE(message(c).find("17 particles: must be in [4, 16]"), std::string::npos);
  c = good;
  c[1].ip = 0;
  EXPECT_NE(message(c).find("listed twice"), std::string::npos);
  c = good;
  c[1].ip = m.numIntegrationPoints();
  EXPECT_NE(message(c).find("out of range"), std::string::npos);
  c = good;
  c[0].distances[0] *= 0.5;
  EXPECT_NE(message(c).find("Euclidean distance"), std::string::npos);
  c = good;
  c[1].particles[4] = c[1].particles[0];
  EXPECT_NE(message(c).find("repeated"), std::string::npos);
  c = good;
  c[1].volume = -1.0;
  EXPECT_NE(message(c).find("volume"), std::string::npos);
  c = good;
  c[1].particles.clear();  // the 4 corners of the lower face of IP 1's DOF cell: coplanar
  const Eigen::Matrix3Xd& X = m.grid().particles;
  double z_low = INFINITY;
  for (const int p : m.ipParticles(1)) z_low = std::min(z_low, X(2, p));
  for (const int p : m.ipParticles(1))
    if (X(2, p) == z_low) c[1].particles.push_back(p);
  ASSERT_EQ(c[1].particles.size(), 4u);
  EXPECT_NE(message(c).find("ill_conditioned"), std::string::npos);
  EXPECT_EQ(m.lumpedMass(), mass);
  EXPECT_EQ(m.ipParticles(0).size(), 8u);
}

}  // namespace
}  // namespace surgical_sim::core
