#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <filesystem>

#include "robot_test_fixtures.h"
#include "surgical_sim/core/robot/compliance_cache.h"
#include "surgical_sim/core/robot/section_compliances.h"
#include "surgical_sim/core/robot/section_condensation.h"
#include "surgical_sim/core/robot/so3.h"
#include "surgical_sim/core/robot/tube_mesh.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::core {
namespace {

// Direct FE check: impose the rigid motion dq = C e_k on the distal face (proximal face
// clamped), solve the interior linear FE problem, and sum the distal reaction forces into a
// wrench about the distal node: it must be the unit load e_k.
TEST(SectionCondensation, CompliancematchesDirectFeSolveUnderUnitLoads) {
  const std::vector<double> st = {0.002, 0.008, 0.014, 0.018};
  const TetMesh mesh = makeTubeMesh(st, 0.002, 0.006, 0.0055, 1, 10);
  const Material mat = Material::create(1e6, 0.45, 1000.0);
  const Eigen::Vector3d p_PD(0.02, 0.0, 0.0);
  const Eigen::Matrix<double, 6, 6> C = condenseSection(mesh, mat, st.front(), st.back(), p_PD);

  const auto model = makeTissueModel(ModelKind::Corotational, mesh, mat);
  Eigen::SparseMatrix<double> K = model->stiffnessPattern();
  model->assembleStiffness(model->restPositions(), TangentMode::Exact, K);
  const int n = mesh.numNodes();
  std::vector<int> interior;
  std::vector<int> slot(n, -1);
  for (int i = 0; i < n; ++i)
    if (mesh.nodes(0, i) > st.front() + 1e-12 && mesh.nodes(0, i) < st.back() - 1e-12) {
      slot[i] = static_cast<int>(interior.size());
      interior.push_back(i);
    }
  // Interior-interior block.
  std::vector<Eigen::Triplet<double>> t;
  for (int c = 0; c < K.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it)
      if (slot[it.row() / 3] >= 0 && slot[c / 3] >= 0)
        t.emplace_back(3 * slot[it.row() / 3] + it.row() % 3, 3 * slot[c / 3] + c % 3, it.value());
  Eigen::SparseMatrix<double> Kii(3 * interior.size(), 3 * interior.size());
  Kii.setFromTriplets(t.begin(), t.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Kii);
  ASSERT_EQ(ldlt.info(), Eigen::Success);

  for (int k = 0; k < 6; ++k) {
    const Eigen::Matrix<double, 6, 1> dq = C.col(k);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(3 * n);
    for (int i = 0; i < n; ++i)
      if (mesh.nodes(0, i) >= st.back() - 1e-12)
        u.segment<3>(3 * i) =
            dq.head<3>() + dq.tail<3>().cross(Eigen::Vector3d(mesh.nodes.col(i)) - p_PD);
    Eigen::VectorXd rhs = -(K * u);
    Eigen::VectorXd b(3 * interior.size());
    for (size_t j = 0; j < interior.size(); ++j)
      b.segment<3>(3 * j) = rhs.segment<3>(3 * interior[j]);
    const Eigen::VectorXd ui = ldlt.solve(b);
    for (size_t j = 0; j < interior.size(); ++j)
      u.segment<3>(3 * interior[j]) = ui.segment<3>(3 * j);
    const Eigen::VectorXd f = K * u;  // force needed to hold the displacement
    Eigen::Matrix<double, 6, 1> wrench = Eigen::Matrix<double, 6, 1>::Zero();
    for (int i = 0; i < n; ++i)
      if (mesh.nodes(0, i) >= st.back() - 1e-12) {
        wrench.head<3>() += f.segment<3>(3 * i);
        wrench.tail<3>() +=
            (Eigen::Vector3d(mesh.nodes.col(i)) - p_PD).cross(Eigen::Vector3d(f.segment<3>(3 * i)));
      }
    const Eigen::Matrix<double, 6, 1> e = Eigen::Matrix<double, 6, 1>::Unit(k);
    EXPECT_LT((wrench - e).norm(), 1e-6) << "unit load " << k << ": " << wrench.transpose();
  }
  EXPECT_LT((C - C.transpose()).norm(), 1e-12 * C.norm());
}

TEST(SectionCondensation, CacheHitReturnsIdenticalCompliance) {
  const std::string dir = testing::TempDir() + "/ss_robot_cache_test";
  std::filesystem::remove_all(dir);
  const ContinuumRobotDescription d = test::smallCableRobot(3);
  const SectionCompliances first = computeSectionCompliances(d, dir);
  EXPECT_EQ(first.cache_hits, 0);
  const SectionCompliances second = computeSectionCompliances(d, dir);
  EXPECT_EQ(second.cache_hits, 3);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(first.compliance[k], second.compliance[k]);
  // A different material is a different key.
  ContinuumRobotDescription e = d;
  e.material.young_modulus *= 2.0;
  EXPECT_NE(sectionCacheKey(d, 0), sectionCacheKey(e, 0));
  const SectionCompliances third = computeSectionCompliances(e, dir);
  EXPECT_EQ(third.cache_hits, 0);
  EXPECT_NEAR(third.compliance[0](0, 0), 0.5 * first.compliance[0](0, 0),
              1e-9 * first.compliance[0](0, 0));
  std::filesystem::remove_all(dir);
}

TEST(SectionCondensation, TubeMeshIsPositiveAndConformingAcrossSeam) {
  const TetMesh m = makeTubeMesh({0.0, 0.01, 0.02}, 0.002, 0.006, 0.004, 2, 9);
  EXPECT_EQ(m.numNodes(), 3 * 3 * 9);
  EXPECT_EQ(m.numElements(), 6 * 2 * 9 * 2);
  double volume = 0.0;
  for (int e = 0; e < m.numElements(); ++e) {
    const Eigen::Vector3d a = m.nodes.col(m.elements(1, e)) - m.nodes.col(m.elements(0, e));
    const Eigen::Vector3d b = m.nodes.col(m.elements(2, e)) - m.nodes.col(m.elements(0, e));
    const Eigen::Vector3d c = m.nodes.col(m.elements(3, e)) - m.nodes.col(m.elements(0, e));
    const double v = a.cross(b).dot(c) / 6.0;
    EXPECT_GT(v, 0.0);
    volume += v;
  }
  EXPECT_GT(volume, 0.0);
}

TEST(SectionCondensation, ValidatorsReject) {
  EXPECT_THROW(makeTubeMesh({0.0}, 0.002, 0.006, 0.006, 1, 8), std::invalid_argument);
  EXPECT_THROW(makeTubeMesh({0.0, -1.0}, 0.002, 0.006, 0.006, 1, 8), std::invalid_argument);
  EXPECT_THROW(makeTubeMesh({0.0, 1.0}, 0.0, 0.006, 0.006, 1, 8), std::invalid_argument);
  EXPECT_THROW(makeTubeMesh({0.0, 1.0}, 0.002, 0.001, 0.006, 1, 8), std::invalid_argument);
  EXPECT_THROW(makeTubeMesh({0.0, 1.0}, 0.002, 0.006, 0.001, 1, 8), std::invalid_argument);
  EXPECT_THROW(makeTubeMesh({0.0, 1.0}, 0.002, 0.006, 0.006, 0, 8), std::invalid_argument);
  EXPECT_THROW(makeTubeMesh({0.0, 1.0}, 0.002, 0.006, 0.006, 1, 5), std::invalid_argument);
  const TetMesh m = makeTubeMesh({0.0, 0.01}, 0.002, 0.006, 0.006, 1, 8);
  const Material mat = Material::create(1e6, 0.45, 1000.0);
  EXPECT_THROW(condenseSection(m, mat, 0.01, 0.0, Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(condenseSection(m, mat, -1.0, 0.01, Eigen::Vector3d::Zero()), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
