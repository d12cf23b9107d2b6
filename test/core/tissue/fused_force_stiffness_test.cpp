// addInternalForceAndStiffness, addInternalForceStiffnessAndEnergy,
// HyperelasticLaw::stressAndTangent and the compact corotational Tet4 stiffness equal the separate
// / generic calls.

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <random>
#include <string>

#include "surgical_sim/core/cutting/cut_tissue_model.h"
#include "surgical_sim/core/tissue/fe_model.h"
#include "surgical_sim/core/tissue/model_factory.h"
#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

// Signed volume of the corner tet of element e at x.
double cornerVolume(const TetMesh& mesh, const Eigen::VectorXd& x, int e) {
  const auto node = [&](int a) -> Eigen::Vector3d { return x.segment<3>(3 * mesh.elements(a, e)); };
  return (node(1) - node(0)).dot((node(2) - node(0)).cross(node(3) - node(0))) / 6.0;
}

// Randomly perturbed cube with element 0 inverted: its node 0 pushed through the opposite face
// (on Tet10 the mid-edge nodes of element 0 follow their straight edges).
Eigen::VectorXd deformedWithInvertedElement(const TetMesh& mesh, std::mt19937& rng) {
  Eigen::VectorXd x = test::perturbed(test::flatten(mesh.nodes), 0.1, rng);
  const int n0 = mesh.elements(0, 0);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int a = 1; a < 4; ++a) centroid += x.segment<3>(3 * mesh.elements(a, 0)) / 3.0;
  x.segment<3>(3 * n0) += 1.7 * (centroid - x.segment<3>(3 * n0));
  if (mesh.type == ElementType::Tet10) {
    constexpr int kEdges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
    for (int k = 0; k < 6; ++k) {
      x.segment<3>(3 * mesh.elements(4 + k, 0)) =
          0.5 * (x.segment<3>(3 * mesh.elements(kEdges[k][0], 0)) +
                 x.segment<3>(3 * mesh.elements(kEdges[k][1], 0)));
    }
  }
  return x;
}

// The fused call adds the same force to a non-zero f and overwrites a garbage-filled K with the
// same values as addInternalForce + assembleStiffness, in both tangent modes.
void expectFusedEqualsSeparate(const TissueModel& model, const Eigen::VectorXd& x,
                               std::mt19937& rng) {
  const Eigen::VectorXd f0 = test::perturbed(Eigen::VectorXd::Zero(x.size()), 1.0, rng);
  Eigen::VectorXd f_separate = f0;
  model.addInternalForce(x, f_separate);
  for (TangentMode mode : {TangentMode::Exact, TangentMode::ProjectedSpd}) {
    Eigen::SparseMatrix<double> K_separate = model.stiffnessPattern();
    model.assembleStiffness(x, mode, K_separate);
    Eigen::SparseMatrix<double> K_fused = model.stiffnessPattern();
    for (Eigen::Index k = 0; k < K_fused.nonZeros(); ++k) K_fused.valuePtr()[k] = 1e9;
    Eigen::VectorXd f_fused = f0;
    model.addInternalForceAndStiffness(x, mode, f_fused, K_fused);
    EXPECT_LT((f_fused - f_separate).norm(), 1e-12 * (f_separate - f0).norm()) << model.name();
    EXPECT_LT(test::relativeError(Eigen::MatrixXd(K_fused), Eigen::MatrixXd(K_separate)), 1e-12)
        << model.name();
    // The same pass with the energy: the same force and stiffness, and energy(x) bit for bit.
    Eigen::SparseMatrix<double> K_with_energy = model.stiffnessPattern();
    for (Eigen::Index k = 0; k < K_with_energy.nonZeros(); ++k) K_with_energy.valuePtr()[k] = 1e9;
    Eigen::VectorXd f_with_energy = f0;
    EXPECT_EQ(model.addInternalForceStiffnessAndEnergy(x, mode, f_with_energy, K_with_energy),
              model.energy(x))
        << model.name();
    EXPECT_LT((f_with_energy - f_fused).norm(), 1e-15 * (f_separate - f0).norm()) << model.name();
    EXPECT_LT(test::relativeError(Eigen::MatrixXd(K_with_energy), Eigen::MatrixXd(K_fused)), 1e-15)
        << model.name();
  }
}

class FusedForceStiffnessTest : public ::testing::TestWithParam<test::LawCase> {
 protected:
  TetMesh mesh() const {
    const TetMesh cube = test::cubeSixTets();
    return GetParam().tet10 ? test::toTet10(cube) : cube;
  }
};

TEST_P(FusedForceStiffnessTest, FeModelEqualsSeparateCallsWithAnInvertedElement) {
  const TetMesh m = mesh();
  const Material material = test::testMaterial(0.3);
  const FeModel model(m, material, test::makeLaw(GetParam().law, material));
  std::mt19937 rng(11);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd x = deformedWithInvertedElement(m, rng);
    ASSERT_LT(cornerVolume(m, x, 0), 0.0);
    expectFusedEqualsSeparate(model, x, rng);
  }
}

TEST_P(FusedForceStiffnessTest, CutTissueModelForwardsToTheElasticModel) {
  const TetMesh m = mesh();
  const Material material = test::testMaterial(0.3);
  auto elastic = std::make_unique<FeModel>(m, material, test::makeLaw(GetParam().law, material));
  const Eigen::VectorXd mass = elastic->lumpedMass();
  const CutTissueModel model(std::move(elastic), mass);
  std::mt19937 rng(12);
  expectFusedEqualsSeparate(model, deformedWithInvertedElement(m, rng), rng);
}

INSTANTIATE_TEST_SUITE_P(AllLaws, FusedForceStiffnessTest, test::allLawCases(), test::lawCaseName);

TEST(FusedForceStiffness, DefaultOfOtherModelsEqualsSeparateCalls) {
  const TetMesh m = test::cubeSixTets();
  std::mt19937 rng(13);
  const Eigen::VectorXd x = deformedWithInvertedElement(m, rng);
  for (const ModelKind kind : {ModelKind::MassSpring, ModelKind::Ems}) {
    expectFusedEqualsSeparate(*makeTissueModel(kind, m, test::testMaterial(0.3)), x, rng);
  }
}

// Forwards the four required functions of a law but none of its fused or compact forms, so that
// FeModel takes the generic 9 x 9 tangent path.
class GenericPathLaw final : public HyperelasticLaw {
 public:
  explicit GenericPathLaw(std::unique_ptr<HyperelasticLaw> law) : law_(std::move(law)) {}
  std::string name() const override { return law_->name(); }
  double energyDensity(const Eigen::Matrix3d& F) const override { return law_->energyDensity(F); }
  Eigen::Matrix3d firstPiola(const Eigen::Matrix3d& F) const override {
    return law_->firstPiola(F);
  }
  Matrix9d firstPiolaDerivative(const Eigen::Matrix3d& F) const override {
    return law_->firstPiolaDerivative(F);
  }
  Matrix9d projectedFirstPiolaDerivative(const Eigen::Matrix3d& F) const override {
    return law_->projectedFirstPiolaDerivative(F);
  }

 private:
  std::unique_ptr<HyperelasticLaw> law_;
};

TEST(RotatedLinearTangent, Tet4CorotationalModelEqualsTheGenericPath) {
  const TetMesh m = test::cubeSixTets();
  const Material material = test::testMaterial(0.3);
  const FeModel compact(m, material, test::makeLaw("corotational", material));
  const FeModel generic(m, material,
                        std::make_unique<GenericPathLaw>(test::makeLaw("corotational", material)));
  std::mt19937 rng(15);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd x = deformedWithInvertedElement(m, rng);
    for (TangentMode mode : {TangentMode::Exact, TangentMode::ProjectedSpd}) {
      Eigen::VectorXd f_compact = Eigen::VectorXd::Zero(x.size());
      Eigen::VectorXd f_generic = Eigen::VectorXd::Zero(x.size());
      Eigen::SparseMatrix<double> K_compact = compact.stiffnessPattern();
      Eigen::SparseMatrix<double> K_generic = generic.stiffnessPattern();
      compact.addInternalForceAndStiffness(x, mode, f_compact, K_compact);
      generic.addInternalForceAndStiffness(x, mode, f_generic, K_generic);
      EXPECT_LT(test::relativeError(f_compact, f_generic), 1e-12);
      EXPECT_LT(test::relativeError(Eigen::MatrixXd(K_compact), Eigen::MatrixXd(K_generic)), 1e-12);
      EXPECT_LT(test::relativeError(test::denseStiffness(compact, x, mode),
                                    test::denseStiffness(generic, x, mode)),
                1e-12);
    }
  }
}

TEST(RotatedLinearTangent, CorotationalCompactFormIsItsProjectedTangent) {
  const Material material = test::testMaterial(0.3);
  const CorotationalLaw law(material);
  std::mt19937 rng(16);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  for (int trial = 0; trial < 6; ++trial) {
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    for (int i = 0; i < 9; ++i) F.data()[i] += u(rng);
    if (trial % 2 == 1) F.col(2) *= -0.6;  // inverted
    const std::optional<RotatedLinearStressAndTangent> compact =
        law.rotatedLinearStressAndTangent(F);
    ASSERT_TRUE(compact.has_value());
    EXPECT_LT((compact->P - law.firstPiola(F)).norm(), 1e-12 * compact->P.norm());
    // Column k + 3 l of the 9 x 9 tangent is dP for dF = e_k e_l^T.
    Matrix9d dPdF;
    for (int c = 0; c < 9; ++c) {
      Eigen::Matrix3d dF = Eigen::Matrix3d::Zero();
      dF.data()[c] = 1.0;
      const Eigen::Matrix3d RtdF = compact->R.transpose() * dF;
      const Eigen::Matrix3d dP =
          compact->R * (compact->mu * (RtdF + RtdF.transpose()) +
                        compact->lambda * RtdF.trace() * Eigen::Matrix3d::Identity());
      dPdF.col(c) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dP.data());
    }
    const Matrix9d projected = law.projectedFirstPiolaDerivative(F);
    EXPECT_LT((dPdF - projected).norm(), 1e-12 * projected.norm());
  }
  for (const char* name : {"svk", "neo_hookean"}) {
    EXPECT_FALSE(
        test::makeLaw(name, material)->rotatedLinearStressAndTangent(Eigen::Matrix3d::Identity()));
  }
}

TEST(StressAndTangent, EqualsSeparateCallsForEveryLaw) {
  const Material material = test::testMaterial(0.3);
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  for (const char* name : {"corotational", "svk", "neo_hookean"}) {
    const std::unique_ptr<HyperelasticLaw> law = test::makeLaw(name, material);
    for (int trial = 0; trial < 6; ++trial) {
      Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
      for (int i = 0; i < 9; ++i) F.data()[i] += u(rng);
      if (trial % 2 == 1) F.col(2) *= -0.6;  // inverted
      for (TangentMode mode : {TangentMode::Exact, TangentMode::ProjectedSpd}) {
        const StressAndTangent fused = law->stressAndTangent(F, mode);
        const Eigen::Matrix3d P = law->firstPiola(F);
        const Matrix9d dPdF = law->tangent(F, mode);
        EXPECT_LT((fused.P - P).norm(), 1e-12 * P.norm()) << name;
        EXPECT_LT((fused.dPdF - dPdF).norm(), 1e-12 * dPdF.norm()) << name;
      }
    }
  }
}

}  // namespace
}  // namespace surgical_sim::core
