#include "surgical_sim/core/connective/rigid_node_model.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <type_traits>

#include "rigid_node_test_util.h"

namespace surgical_sim::core {
namespace {

using test::displaced;
using test::perturbed;
using test::randomLayout;

Eigen::MatrixXd stiffness(const RigidNodeModel& model, const RigidNodeConfiguration& q,
                          bool material, bool geometric, bool symmetrize) {
  Eigen::SparseMatrix<double> K = model.stiffnessPattern();
  RigidNodeTangentOptions options;
  options.material = material;
  options.geometric = geometric;
  options.symmetrize = symmetrize;
  model.assembleStiffness(q, options, K);
  return Eigen::MatrixXd(K);
}

Eigen::VectorXd force(const RigidNodeModel& model, const RigidNodeConfiguration& q) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.numDofs());
  model.addInternalForce(q, f);
  return f;
}

/// -sum_s M_s(q_M)^T {S_s(q_S)} v_s: the force with the strain Jacobian and the stress taken at
/// two configurations (the material tangent varies q_S, the geometric one q_M).
Eigen::VectorXd splitForce(const RigidNodeModel& model, const RigidNodeConfiguration& q_M,
                           const RigidNodeConfiguration& q_S) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.numDofs());
  for (int s = 0; s < model.numSamples(); ++s) {
    const SampleKinematics kin = model.sampleKinematics(q_M, s);
    const Vector6d S = model.sampleStress(s, model.sampleKinematics(q_S, s).F);
    const RigidNodeSample& sample = model.samples()[s];
    for (size_t a = 0; a < sample.weights.nodes.size(); ++a)
      f.segment<6>(kRigidNodeDofs * sample.weights.nodes[a]) -=
          sample.volume * kin.M[a].transpose() * S;
  }
  return f;
}

/// (g(q (+) h e_k) - g(q (+) -h e_k)) / 2h, h = 1e-6 rad for rotations, 1e-6 L for translations.
template <class G>
auto centralDifference(const RigidNodeConfiguration& q, int k, double L, G&& g)
    -> std::decay_t<decltype(g(q))> {
  const double h = k % kRigidNodeDofs >= 3 ? 1e-6 : 1e-6 * L;
  return (g(displaced(q, k, h)) - g(displaced(q, k, -h))) / (2.0 * h);
}

Eigen::Matrix<double, 6, 1> voigtStrain(const Eigen::Matrix3d& F) {
  const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
  Eigen::Matrix<double, 6, 1> e;
  e << E(0, 0), E(1, 1), E(2, 2), 2 * E(1, 2), 2 * E(0, 2), 2 * E(0, 1);
  return e;
}

/// A random layout at length scale L, its model and a configuration perturbed by `amplitude`.
struct RandomCase {
  RandomCase(unsigned seed, int nodes, int samples, int neighbours, double L, unsigned q_seed,
             double amplitude)
      : layout(randomLayout(seed, nodes, samples, neighbours, L)),
        model(layout.rest, layout.samples),
        q(perturbed(layout.rest, q_seed, amplitude, L)) {}
  RigidNodeLayout layout;
  RigidNodeModel model;
  RigidNodeConfiguration q;
};

class RigidNodeModelAtScale : public ::testing::TestWithParam<double> {};

TEST_P(RigidNodeModelAtScale, RestAndRigidMotionsGiveIdentityStrainAndZeroForce) {
  const double L = GetParam();
  const RigidNodeLayout layout = randomLayout(7, 6, 12, 4, L);
  const RigidNodeModel model(layout.rest, layout.samples);
  const double stress_scale = 1e3;  // Lame parameters of randomLayout [Pa]
  const double force_tolerance = 1e-12 * stress_scale * L * L;
  EXPECT_NEAR(model.energy(layout.rest), 0.0, 1e-20 * L * L * L);
  EXPECT_LE(force(model, layout.rest).cwiseAbs().maxCoeff(), force_tolerance);
  for (int s = 0; s < model.numSamples(); ++s) {
    EXPECT_LE((model.sampleKinematics(layout.rest, s).F - Eigen::Matrix3d::Identity()).norm(),
              1e-12);
    EXPECT_LE((model.samplePosition(layout.rest, s) - layout.samples[s].rest_position).norm(),
              1e-12 * L);
  }
  const Eigen::Quaterniond R = expRotation(Eigen::Vector3d(0.7, -1.9, 2.4));
  const Eigen::Vector3d t = L * Eigen::Vector3d(3.0, -1.0, 2.0);
  const RigidNodeConfiguration moved = test::rigidlyMoved(layout.rest, R, t);
  EXPECT_NEAR(model.energy(moved), 0.0, 1e-20 * L * L * L);
  EXPECT_LE(force(model, moved).cwiseAbs().maxCoeff(), force_tolerance);
  for (int s = 0; s < model.numSamples(); ++s) {
    EXPECT_LE((model.sampleKinematics(moved, s).F - R.toRotationMatrix()).norm(), 1e-12);
    EXPECT_LE((model.samplePosition(moved, s) - (R * layout.samples[s].rest_position + t)).norm(),
              1e-12 * L);
  }
}

TEST_P(RigidNodeModelAtScale, ForceIsMinusTheEnergyGradient) {
  const double L = GetParam();
  const RandomCase c(8, 5, 10, 4, L, 21, 0.15);
  const auto& [layout, model, q] = c;
  const Eigen::VectorXd f = force(model, q);
  for (int k = 0; k < model.numDofs(); ++k) {
    const bool rotation = k % kRigidNodeDofs >= 3;
    const double fd = -centralDifference(q, k, L, [&](const auto& x) { return model.energy(x); });
    EXPECT_NEAR(f[k], fd,
                1e-6 * f.cwiseAbs().maxCoeff() * (rotation ? 1.0 / L : 1.0) + 1e-7 * std::abs(f[k]))
        << "dof " << k;
  }
}

TEST_P(RigidNodeModelAtScale, DeformationGradientAndStrainJacobiansMatchFiniteDifferences) {
  // Catches Eq. 3.49's "F00 [B]^4" (the row of d(2 E01) takes F00 [B]^3) and the skew matrix's
  // last row (Eq. A.3).
  const double L = GetParam();
  const RandomCase c(9, 5, 6, 4, L, 22, 0.2);
  const auto& [layout, model, q] = c;
  for (int s = 0; s < model.numSamples(); ++s) {
    const SampleKinematics kin = model.sampleKinematics(q, s);
    const std::vector<int>& nodes = layout.samples[s].weights.nodes;
    for (size_t a = 0; a < nodes.size(); ++a) {
      for (int c = 0; c < kRigidNodeDofs; ++c) {
        const double h = c >= 3 ? 1e-6 : 1e-6 * L;
        const int dof = kRigidNodeDofs * nodes[a] + c;
        const Eigen::Matrix3d Fp = model.sampleKinematics(displaced(q, dof, h), s).F;
        const Eigen::Matrix3d Fm = model.sampleKinematics(displaced(q, dof, -h), s).F;
        const Eigen::Matrix3d dF = (Fp - Fm) / (2.0 * h);
        const Eigen::Matrix<double, 9, 1> dF_stacked =
            Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dF.data());  // column by column
        const double unit = c >= 3 ? 1.0 : 1.0 / L;
        EXPECT_LE((kin.B[a].col(c) - dF_stacked).norm(), 1e-7 * unit) << "sample " << s;
        const Vector6d dE = (voigtStrain(Fp) - voigtStrain(Fm)) / (2.0 * h);
        EXPECT_LE((kin.M[a].col(c) - dE).norm(), 1e-7 * unit) << "sample " << s;
      }
    }
  }
}

/// The material, geometric and full tangents of model at q against differences of the force
/// (with the strain Jacobian, the stress or nothing frozen), their symmetry, the fused call; at
/// rest a positive semi-definite tangent whose null space has dimension `null_space` (the six
/// rigid motions plus any drilling modes; not checked if negative). L: length scale [m].
void expectTangentsMatchDifferences(const RigidNodeModel& model, const RigidNodeConfiguration& q,
                                    double L, int null_space) {
  const int n = model.numDofs();
  // Column k in length units: translations 1/L relative to rotations.
  Eigen::MatrixXd units = Eigen::MatrixXd::Ones(n, n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c)
      units(r, c) = (r % 6 < 3 ? 1.0 / L : 1.0) * (c % 6 < 3 ? 1.0 / L : 1.0);
  auto expectClose = [&](const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& fd,
                         const char* what) {
    const Eigen::MatrixXd scaled_error = (analytic - fd).cwiseQuotient(units);
    const double scale = analytic.cwiseQuotient(units).cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 0.0) << what;
    EXPECT_LE(scaled_error.cwiseAbs().maxCoeff(), 1e-6 * scale) << what;
  };
  // Differences per column with a step in the column's unit.
  auto columns = [&](auto&& g) {
    Eigen::MatrixXd K(n, n);
    for (int k = 0; k < n; ++k) K.col(k) = -centralDifference(q, k, L, g);
    return K;
  };
  const Eigen::MatrixXd K_mat = stiffness(model, q, true, false, false);
  const Eigen::MatrixXd K_geo = stiffness(model, q, false, true, false);
  const Eigen::MatrixXd K_full = stiffness(model, q, true, true, false);
  expectClose(K_mat,
              columns([&](const RigidNodeConfiguration& x) { return splitForce(model, q, x); }),
              "material (stress varied, strain Jacobian fixed)");
  expectClose(K_geo,
              columns([&](const RigidNodeConfiguration& x) { return splitForce(model, x, q); }),
              "geometric (strain Jacobian varied, stress fixed)");
  expectClose(K_full, columns([&](const RigidNodeConfiguration& x) { return force(model, x); }),
              "full tangent");
  EXPECT_LE((K_mat - K_mat.transpose()).cwiseAbs().maxCoeff(), 1e-12 * K_mat.cwiseAbs().maxCoeff());
  const Eigen::MatrixXd K_sym = stiffness(model, q, true, true, true);
  EXPECT_LE((K_sym - 0.5 * (K_full + K_full.transpose())).cwiseAbs().maxCoeff(),
            1e-12 * K_full.cwiseAbs().maxCoeff());
  // Fused force and stiffness equal the separate calls.
  Eigen::SparseMatrix<double> K = model.stiffnessPattern();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
  model.addInternalForceAndStiffness(q, RigidNodeTangentOptions{}, f, K);
  EXPECT_LE((Eigen::MatrixXd(K) - K_sym).cwiseAbs().maxCoeff(),
            1e-13 * K_sym.cwiseAbs().maxCoeff());
  EXPECT_LE((f - force(model, q)).cwiseAbs().maxCoeff(), 1e-13 * f.cwiseAbs().maxCoeff());
  // At rest the tangent is the material part, symmetric positive semi-definite (translations
  // scaled by L so that all entries are in N m).
  Eigen::VectorXd to_length = Eigen::VectorXd::Ones(n);
  for (int k = 0; k < n; ++k)
    if (k % 6 < 3) to_length[k] = L;
  const Eigen::MatrixXd K_rest = to_length.asDiagonal() *
                                 stiffness(model, model.restConfiguration(), true, true, false) *
                                 to_length.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(K_rest);
  const double largest = eig.eigenvalues().maxCoeff();
  EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-10 * largest);
  if (null_space < 0) return;
  EXPECT_LE(eig.eigenvalues()[null_space - 1], 1e-10 * largest);
  EXPECT_GT(eig.eigenvalues()[null_space], 1e-8 * largest);
}

TEST_P(RigidNodeModelAtScale, MaterialAndGeometricTangentsMatchFiniteDifferencesSeparately) {
  const double L = GetParam();
  const RandomCase c(10, 4, 8, 3, L, 23, 0.2);
  expectTangentsMatchDifferences(c.model, c.q, L, 6);
}

/// A trilinear grid: 27 samples per cell share their 8 rigid nodes (assembled per cell).
TEST_P(RigidNodeModelAtScale, TrilinearGridTangentsMatchFiniteDifferences) {
  const double L = GetParam();
  const RigidNodeLayout layout =
      trilinearGridLayout(Eigen::Vector3d(-0.2, 0.1, 0.3) * L, Eigen::Vector3d(1.0, 0.8, 0.6) * L,
                          Eigen::Vector3i(2, 2, 3), Material::create(1e4, 0.3, 1000.0));
  const RigidNodeModel model(layout.rest, layout.samples);
  // Rigid motions and one drilling mode per grid plane: 6 + 2 + 2 + 3.
  expectTangentsMatchDifferences(model, perturbed(layout.rest, 26, 0.2, L), L, 13);
}

TEST_P(RigidNodeModelAtScale, BodyForceAndItsTangentMatchTheirPotential) {
  const double L = GetParam();
  const RandomCase c(12, 4, 8, 3, L, 24, 0.3);
  const auto& [layout, model, q] = c;
  const Eigen::Vector3d g(0.3, -9.81, 1.2);
  auto bodyForce = [&](const RigidNodeConfiguration& x) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(model.numDofs());
    model.addBodyForce(x, g, f);
    return f;
  };
  const Eigen::VectorXd f = bodyForce(q);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int i = 0; i < model.numNodes(); ++i) total += f.segment<3>(kRigidNodeDofs * i);
  EXPECT_LE((total - model.totalMass() * g).norm(), 1e-12 * model.totalMass() * g.norm());
  Eigen::SparseMatrix<double> K = model.stiffnessPattern();
  K.coeffs().setZero();
  model.addBodyForceStiffness(q, g, false, K);
  // Translational entries in N, rotational ones in N m.
  const double weight = model.totalMass() * g.norm();
  for (int k = 0; k < model.numDofs(); ++k) {
    const bool rotation = k % 6 >= 3;
    const double fd =
        -centralDifference(q, k, L, [&](const auto& x) { return model.bodyForcePotential(x, g); });
    EXPECT_NEAR(f[k], fd, 1e-7 * weight * (rotation ? L : 1.0)) << "dof " << k;
    const Eigen::VectorXd column = -centralDifference(q, k, L, bodyForce);
    EXPECT_LE((Eigen::VectorXd(Eigen::MatrixXd(K).col(k)) - column).norm(),
              1e-6 * weight * L * (rotation ? 1.0 : 1.0 / L))
        << "dof " << k;
  }
}

TEST_P(RigidNodeModelAtScale, ConsistentMassGivesTheSamplesKineticEnergy) {
  const double L = GetParam();
  const RandomCase c(13, 5, 12, 4, L, 25, 0.3);
  const auto& [layout, model, q] = c;
  Eigen::SparseMatrix<double> M = model.stiffnessPattern();
  model.assembleMass(q, M);
  const Eigen::MatrixXd Md(M);
  EXPECT_LE((Md - Md.transpose()).cwiseAbs().maxCoeff(), 1e-14 * Md.cwiseAbs().maxCoeff());
  // Any node velocities: qdot^T M qdot = sum_s m_s |pdot_s|^2 with pdot_s by differences.
  std::mt19937 rng(4);
  Eigen::VectorXd qdot(model.numDofs());
  for (int i = 0; i < model.numNodes(); ++i) {
    qdot.segment<3>(6 * i) = L * test::randomVector(rng, 1.0);
    qdot.segment<3>(6 * i + 3) = test::randomVector(rng, 1.0);
  }
  const double h = 1e-7;
  RigidNodeConfiguration plus = q, minus = q;
  applyRigidNodeIncrement(qdot, h, plus);
  applyRigidNodeIncrement(qdot, -h, minus);
  double kinetic = 0.0;
  for (int s = 0; s < model.numSamples(); ++s) {
    const Eigen::Vector3d v =
        (model.samplePosition(plus, s) - model.samplePosition(minus, s)) / (2.0 * h);
    kinetic += 0.5 * layout.samples[s].density * layout.samples[s].volume * v.squaredNorm();
  }
  EXPECT_NEAR(0.5 * qdot.dot(Md * qdot), kinetic, 1e-6 * kinetic);
  // A common translation: the total mass.
  Eigen::VectorXd translation = Eigen::VectorXd::Zero(model.numDofs());
  for (int i = 0; i < model.numNodes(); ++i) translation[6 * i + 1] = 1.0;
  EXPECT_NEAR(translation.dot(Md * translation), model.totalMass(), 1e-12 * model.totalMass());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Md);
  EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12 * eig.eigenvalues().maxCoeff());

  // The rigid-node (block-diagonal) mass: exact for rigid motions at rest, positive definite.
  Eigen::SparseMatrix<double> N = model.stiffnessPattern();
  model.assembleNodeMass(layout.rest, N);
  const Eigen::Vector3d V = L * Eigen::Vector3d(0.3, -1.0, 0.5), omega(0.2, 0.7, -0.4);
  Eigen::VectorXd rigid(model.numDofs());
  double rigid_kinetic = 0.0;
  for (int i = 0; i < model.numNodes(); ++i) {
    rigid.segment<3>(6 * i) = V + omega.cross(layout.rest.p_TN[i]);
    rigid.segment<3>(6 * i + 3) = omega;
  }
  for (const RigidNodeSample& s : layout.samples)
    rigid_kinetic += 0.5 * s.density * s.volume * (V + omega.cross(s.rest_position)).squaredNorm();
  EXPECT_NEAR(0.5 * rigid.dot(N * rigid), rigid_kinetic, 1e-12 * rigid_kinetic);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> node_eig{Eigen::MatrixXd(N)};
  EXPECT_GT(node_eig.eigenvalues().minCoeff(), 0.0);
}

INSTANTIATE_TEST_SUITE_P(Lengths, RigidNodeModelAtScale, ::testing::Values(1e-3, 1.0, 1e3),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return info.param == 1e-3  ? std::string("mm")
                                  : info.param == 1.0 ? std::string("m")
                                                      : std::string("km");
                         });

TEST(RigidNodeModel, BadInputIsRejectedWithTheProblemNamed) {
  const RigidNodeLayout good = randomLayout(14, 4, 6, 3);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto build = [](const RigidNodeLayout& layout) { RigidNodeModel(layout.rest, layout.samples); };
  RigidNodeLayout bad = good;
  bad.samples[2].volume = 0.0;
  test::expectInvalidArgument([&] { build(bad); }, "sample 2 volume = 0 m^3 is out of range");
  bad = good;
  bad.samples[1].rest_position.y() = nan;
  test::expectInvalidArgument([&] { build(bad); }, "sample 1 rest_position");
  bad = good;
  bad.rest.p_TN[3].x() = nan;
  test::expectInvalidArgument([&] { build(bad); }, "rigid node 3 position");
  bad = good;
  bad.samples[0].weights.weights[0] *= 0.9;
  test::expectInvalidArgument([&] { build(bad); }, "sample 0 weights: weights sum to");
  bad = good;
  bad.rest.q_TN[2].coeffs() *= 1.01;
  test::expectInvalidArgument([&] { build(bad); }, "rigid node 2 quaternion norm 1.01");
  bad = good;
  bad.samples[3].mu = -1.0;
  test::expectInvalidArgument([&] { build(bad); }, "sample 3 mu");
  bad = good;
  bad.samples[3].density = nan;
  test::expectInvalidArgument([&] { build(bad); }, "sample 3 density");
  bad = good;
  bad.rest.p_TN.push_back(Eigen::Vector3d::Zero());
  bad.rest.q_TN.push_back(Eigen::Quaterniond::Identity());
  test::expectInvalidArgument([&] { build(bad); }, "rigid node 4 is a neighbour of no sample");

  const RigidNodeModel model(good.rest, good.samples);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(5);
  test::expectInvalidArgument([&] { model.addInternalForce(good.rest, f); }, "must be 24");
  Eigen::SparseMatrix<double> K(24, 24);
  test::expectInvalidArgument(
      [&] { model.assembleStiffness(good.rest, RigidNodeTangentOptions{}, K); },
      "must have stiffnessPattern()");
}

}  // namespace
}  // namespace surgical_sim::core
