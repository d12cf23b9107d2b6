#include "surgical_sim/core/tissue/fe_rest_data.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "surgical_sim/core/tissue/tissue_mesh_check.h"
#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

constexpr double kDensity = 1000.0;

double maxAbs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

double maxAbsDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0.0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

TetMesh randomMesh() {
  std::mt19937 rng(7);
  TetMesh mesh = test::jitteredLattice(4, 0.01, 0.002, rng);
  checkTissueMesh(mesh, "corotational", false);  // a valid mesh: the precondition of both paths
  return mesh;
}

TEST(FeRestData, Tet4ClosedFormEqualsGenericQuadrature) {
  const TetMesh mesh = randomMesh();
  const FeRestData fast = computeFeRestData(mesh, kDensity);
  const FeRestData generic = computeFeRestData(mesh, kDensity, FeRestEvaluation::Generic);
  ASSERT_EQ(fast.points_per_element, 1);
  ASSERT_EQ(generic.points_per_element, 1);
  ASSERT_EQ(fast.rest_gradients.size(), generic.rest_gradients.size());
  ASSERT_EQ(fast.weight_det_j.size(), generic.weight_det_j.size());
  EXPECT_LE(maxAbsDifference(fast.rest_gradients, generic.rest_gradients),
            1e-14 * maxAbs(generic.rest_gradients));
  EXPECT_LE(maxAbsDifference(fast.weight_det_j, generic.weight_det_j),
            1e-14 * maxAbs(generic.weight_det_j));
  EXPECT_LE((fast.lumped_mass - generic.lumped_mass).lpNorm<Eigen::Infinity>(),
            1e-14 * generic.lumped_mass.lpNorm<Eigen::Infinity>());
  EXPECT_LE((fast.body_weight - generic.body_weight).lpNorm<Eigen::Infinity>(),
            1e-14 * generic.body_weight.lpNorm<Eigen::Infinity>());
}

TEST(FeRestData, Tet4GradientsInterpolateTheRestShape) {
  // Linear shape functions reproduce constants (gradients sum to zero) and the rest positions
  // (sum_a X_a dN_a/dX = I); w det J is the element volume and the mass sums to rho V.
  const TetMesh mesh = randomMesh();
  const FeRestData data = computeFeRestData(mesh, kDensity);
  double volume = 0.0;
  for (int e = 0; e < mesh.numElements(); ++e) {
    const Eigen::Map<const Eigen::Matrix<double, 4, 3>> G(data.rest_gradients.data() + 12 * e);
    Eigen::Matrix<double, 3, 4> X;
    for (int a = 0; a < 4; ++a) X.col(a) = mesh.nodes.col(mesh.elements(a, e));
    EXPECT_LT(G.colwise().sum().norm(), 1e-12 * G.norm());
    EXPECT_LT((X * G - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    const double V = signedTetVolume(X.col(0), X.col(1), X.col(2), X.col(3));
    EXPECT_NEAR(data.weight_det_j[static_cast<size_t>(e)], V, 1e-12 * V);
    volume += V;
  }
  EXPECT_NEAR(data.lumped_mass.sum(), 3.0 * kDensity * volume, 1e-12 * kDensity * volume);
  EXPECT_NEAR(data.body_weight.sum(), kDensity * volume, 1e-12 * kDensity * volume);
}

TEST(FeRestData, Tet10TakesTheGenericQuadrature) {
  const TetMesh mesh = test::toTet10(randomMesh());
  const FeRestData fast = computeFeRestData(mesh, kDensity);
  const FeRestData generic = computeFeRestData(mesh, kDensity, FeRestEvaluation::Generic);
  EXPECT_EQ(fast.points_per_element, 4);
  EXPECT_EQ(fast.rest_gradients.size(), static_cast<size_t>(mesh.numElements()) * 4 * 10 * 3);
  EXPECT_EQ(fast.rest_gradients, generic.rest_gradients);
  EXPECT_EQ(fast.weight_det_j, generic.weight_det_j);
  EXPECT_EQ(fast.lumped_mass, generic.lumped_mass);
  EXPECT_EQ(fast.body_weight, generic.body_weight);
}

TEST(FeRestData, InvertedElementIsNamedByBothEvaluations) {
  TetMesh mesh = test::twoTets();
  std::swap(mesh.elements(2, 1), mesh.elements(3, 1));
  for (FeRestEvaluation evaluation : {FeRestEvaluation::Fastest, FeRestEvaluation::Generic}) {
    try {
      computeFeRestData(mesh, kDensity, evaluation);
      FAIL() << "inverted rest element accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("mesh.elements: element 1"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace surgical_sim::core
