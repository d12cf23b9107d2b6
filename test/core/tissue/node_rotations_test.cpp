#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/tissue/efg_model.h"
#include "surgical_sim/core/tissue/fe_model.h"
#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

TetMesh beam(ElementType type) { return makeBeam(0.2, 0.04, 0.03, {5, 2, 2}, type); }

/// The models with node rotations: corotational Tet4 and neo-Hookean Tet10 FE, EFG.
std::vector<std::unique_ptr<TissueModel>> models() {
  const Material material = test::testMaterial(0.3);
  std::vector<std::unique_ptr<TissueModel>> all;
  all.push_back(std::make_unique<FeModel>(beam(ElementType::Tet4), material,
                                          test::makeLaw("corotational", material)));
  all.push_back(std::make_unique<FeModel>(beam(ElementType::Tet10), material,
                                          test::makeLaw("neo_hookean", material)));
  EfgOptions efg;
  efg.spacing = 0.02;
  all.push_back(std::make_unique<EfgModel>(beam(ElementType::Tet4), material, efg));
  return all;
}

/// Max over nodes of |rotations[i] - R| (Frobenius).
double maxDeviation(const std::vector<Eigen::Matrix3d>& rotations, const Eigen::Matrix3d& R) {
  double deviation = 0.0;
  for (const Eigen::Matrix3d& Ri : rotations) deviation = std::max(deviation, (Ri - R).norm());
  return deviation;
}

TEST(NodeRotations, RestGivesIdentityAndRigidRotationGivesTheRotation) {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(2.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.4, -1.0, 0.25);
  for (const auto& model : models()) {
    const Eigen::VectorXd& rest = model->restPositions();
    std::vector<Eigen::Matrix3d> rotations;
    ASSERT_TRUE(model->nodeRotations(rest, rotations)) << model->name();
    ASSERT_EQ(static_cast<int>(rotations.size()), model->numNodes()) << model->name();
    EXPECT_LT(maxDeviation(rotations, Eigen::Matrix3d::Identity()), 1e-12) << model->name();

    Eigen::VectorXd moved(rest.size());
    for (int i = 0; i < model->numNodes(); ++i) {
      moved.segment<3>(3 * i) = R * rest.segment<3>(3 * i) + t;
    }
    ASSERT_TRUE(model->nodeRotations(moved, rotations)) << model->name();
    EXPECT_LT(maxDeviation(rotations, R), 1e-12) << model->name();
  }
}

TEST(NodeRotations, StretchAlongTheAxesIsNoRotation) {
  for (const auto& model : models()) {
    Eigen::VectorXd stretched = model->restPositions();
    for (int i = 0; i < model->numNodes(); ++i) {
      stretched.segment<3>(3 * i).array() *= Eigen::Array3d(1.3, 0.8, 1.1);
    }
    std::vector<Eigen::Matrix3d> rotations;
    ASSERT_TRUE(model->nodeRotations(stretched, rotations));
    EXPECT_LT(maxDeviation(rotations, Eigen::Matrix3d::Identity()), 1e-12) << model->name();
  }
}

}  // namespace
}  // namespace surgical_sim::core
