#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "robot_test_fixtures.h"
#include "surgical_sim/core/robot/chamber_pressure_model.h"
#include "surgical_sim/core/robot/pressure_chamber_actuator.h"
#include "surgical_sim/core/robot/tube_mesh.h"

namespace surgical_sim::core {
namespace {

struct ChamberInTube {
  ContinuumRobotDescription d = test::smallPressureRobot();
  TetMesh mesh;
  std::unique_ptr<ChamberPressureModel> model;
  ChamberInTube() {
    std::vector<double> stations;
    for (int i = 0; i <= 8; ++i) stations.push_back(d.length() * i / 8.0);
    stations.insert(stations.begin() + 1, 0.5 * d.vertebra_thickness);
    mesh = makeTubeMesh(stations, d.inner_radius, d.outer_radius_base, d.outer_radius_tip, 1, 8);
    std::vector<RigidNodePose> rest(d.num_vertebrae + 1);
    for (int k = 0; k <= d.num_vertebrae; ++k) rest[k].p_BN.x() = k * d.vertebra_spacing;
    const PressureChamberActuator chamber(d.chambers[0], d, 12, 1);
    model = std::make_unique<ChamberPressureModel>(mesh, chamber.vertexPositions(rest),
                                                   chamber.triangles());
    model->setPressure(1e5);
  }
};

// Volume of the embedded cavity at rest = pi r^2 * (chamber length) up to the polygon factor, and
// a rigid motion of the mesh leaves it unchanged (closed surface).
TEST(ChamberPressureModel, VolumeIsTheCavityVolumeAndRigidInvariant) {
  ChamberInTube c;
  const Eigen::VectorXd x0 = c.model->restPositions();
  const double ell = c.d.vertebra_spacing - c.d.vertebra_thickness;
  const double polygon = 12.0 / (2.0 * M_PI) * std::sin(2.0 * M_PI / 12.0);  // area ratio
  const double expected = polygon * M_PI * 1e-6 * ell * c.d.num_vertebrae;
  EXPECT_NEAR(c.model->volume(x0), expected, 1e-12 * expected);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  Eigen::VectorXd x = x0;
  for (int i = 0; i < x.size() / 3; ++i)
    x.segment<3>(3 * i) = R * x0.segment<3>(3 * i) + Eigen::Vector3d(0.1, -0.2, 0.3);
  EXPECT_NEAR(c.model->volume(x), expected, 1e-10 * expected);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  c.model->addInternalForce(x, f);
  Eigen::Vector3d net = Eigen::Vector3d::Zero();
  for (int i = 0; i < x.size() / 3; ++i) net += f.segment<3>(3 * i);
  EXPECT_LT(net.norm(), 1e-9 * 1e5 * M_PI * 1e-6);
}

// Force = -dE/dx and exact stiffness = -df/dx by central differences at a deformed state.
TEST(ChamberPressureModel, ForceAndStiffnessMatchFiniteDifferences) {
  ChamberInTube c;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd x = c.model->restPositions();
  for (int i = 0; i < x.size(); ++i) x[i] += 2e-4 * u(rng);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size()), v(x.size());
  for (int i = 0; i < v.size(); ++i) v[i] = u(rng);
  c.model->addInternalForce(x, f);
  const double h = 1e-7;
  const double dE = (c.model->energy(x + h * v) - c.model->energy(x - h * v)) / (2.0 * h);
  EXPECT_NEAR(-dE, f.dot(v), 1e-6 * std::abs(f.dot(v)) + 1e-12);

  Eigen::VectorXd fp = Eigen::VectorXd::Zero(x.size()), fm = fp, Kv = fp, Kv_assembled;
  c.model->addInternalForce(x + h * v, fp);
  c.model->addInternalForce(x - h * v, fm);
  const Eigen::VectorXd fd = -(fp - fm) / (2.0 * h);
  c.model->applyStiffness(x, TangentMode::Exact, v, Kv);
  Eigen::SparseMatrix<double> K = c.model->stiffnessPattern();
  c.model->assembleStiffness(x, TangentMode::Exact, K);
  Kv_assembled = K * v;
  EXPECT_LT((Kv - fd).norm(), 1e-6 * fd.norm());
  EXPECT_LT((Kv_assembled - fd).norm(), 1e-6 * fd.norm());
  EXPECT_LT((Eigen::MatrixXd(K) - Eigen::MatrixXd(K).transpose()).norm(), 1e-9 * K.norm());
  c.model->applyStiffness(x, TangentMode::ProjectedSpd, v, Kv);
  EXPECT_EQ(Kv.norm(), 0.0);
}

TEST(ChamberPressureModel, RejectsVertexOutsideTheMesh) {
  ChamberInTube c;
  const std::vector<Eigen::Vector3d> outside = {Eigen::Vector3d(0.01, 0.0, 0.5)};
  EXPECT_THROW(ChamberPressureModel(c.mesh, outside, {}), std::invalid_argument);
  const std::vector<Eigen::Vector3d> inside = {Eigen::Vector3d(0.01, 0.0, 0.004)};
  EXPECT_THROW(ChamberPressureModel(c.mesh, inside, {Eigen::Vector3i(0, 0, 1)}),
               std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
