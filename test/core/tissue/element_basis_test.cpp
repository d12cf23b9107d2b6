#include "surgical_sim/core/tissue/element_basis.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

// Reference coordinates of the Tet10 nodes (corners then mid-edges in Gmsh order).
Eigen::Matrix<double, 3, 10> referenceNodes() {
  Eigen::Matrix<double, 3, 10> P;
  P.leftCols<4>() << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  const int pairs[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
  for (int m = 0; m < 6; ++m) P.col(4 + m) = 0.5 * (P.col(pairs[m][0]) + P.col(pairs[m][1]));
  return P;
}

double factorial(int k) { return std::tgamma(k + 1.0); }

// Exact integral of xi^a eta^b zeta^c over the reference tet: a! b! c! / (a + b + c + 3)!.
double monomialIntegral(int a, int b, int c) {
  return factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
}

double integrate(const QuadratureRule& rule, int a, int b, int c) {
  double sum = 0.0;
  for (int q = 0; q < rule.weights.size(); ++q) {
    const Eigen::Vector3d p = rule.points.col(q);
    sum += rule.weights(q) * std::pow(p(0), a) * std::pow(p(1), b) * std::pow(p(2), c);
  }
  return sum;
}

int exactDegree(const QuadratureRule& rule) {
  for (int degree = 0; degree <= 8; ++degree) {
    for (int a = 0; a <= degree; ++a) {
      for (int b = 0; a + b <= degree; ++b) {
        const int c = degree - a - b;
        if (std::abs(integrate(rule, a, b, c) - monomialIntegral(a, b, c)) >
            1e-14 * monomialIntegral(a, b, c) * 50) {
          return degree - 1;
        }
      }
    }
  }
  return 8;
}

TEST(ElementBasis, NodeCountsAndQuadratureDegrees) {
  const ElementBasis tet4(ElementType::Tet4);
  const ElementBasis tet10(ElementType::Tet10);
  EXPECT_EQ(tet4.numNodes(), 4);
  EXPECT_EQ(tet10.numNodes(), 10);
  EXPECT_EQ(tet4.stiffnessRule().weights.size(), 1);
  EXPECT_EQ(tet10.stiffnessRule().weights.size(), 4);
  EXPECT_GE(exactDegree(tet4.stiffnessRule()), 1);
  EXPECT_EQ(exactDegree(tet10.stiffnessRule()), 2);
  EXPECT_GE(exactDegree(tet4.massRule()), 2);
  EXPECT_GE(exactDegree(tet10.massRule()), 4);  // N_a N_b on affine Tet10 is degree 4
  EXPECT_GT(tet10.massRule().weights.minCoeff(), 0.0);
  for (const auto* rule : {&tet4.stiffnessRule(), &tet10.stiffnessRule(), &tet10.massRule()}) {
    EXPECT_NEAR(rule->weights.sum(), 1.0 / 6.0, 1e-15);
  }
}

TEST(ElementBasis, KroneckerPropertyAndPartitionOfUnity) {
  const Eigen::Matrix<double, 3, 10> P = referenceNodes();
  for (ElementType type : {ElementType::Tet4, ElementType::Tet10}) {
    const ElementBasis basis(type);
    const int npe = basis.numNodes();
    for (int b = 0; b < npe; ++b) {
      const Eigen::VectorXd N = basis.shapeValues(P.col(b));
      for (int a = 0; a < npe; ++a) EXPECT_NEAR(N(a), a == b ? 1.0 : 0.0, 1e-15);
    }
    const Eigen::Vector3d xi(0.21, 0.13, 0.37);
    EXPECT_NEAR(basis.shapeValues(xi).sum(), 1.0, 1e-15);
    EXPECT_LT(basis.shapeGradients(xi).colwise().sum().norm(), 1e-14);
  }
}

TEST(ElementBasis, GradientsMatchFiniteDifferences) {
  const ElementBasis basis(ElementType::Tet10);
  const Eigen::Vector3d xi(0.21, 0.13, 0.37);
  const Eigen::MatrixXd dN = basis.shapeGradients(xi);
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d dxi = h * Eigen::Vector3d::Unit(k);
    const Eigen::VectorXd fd =
        (basis.shapeValues(xi + dxi) - basis.shapeValues(xi - dxi)) / (2 * h);
    EXPECT_LT((fd - dN.col(k)).norm(), 1e-9);
  }
}

TEST(ElementBasis, RestGradientsReproduceLinearFields) {
  // On a straight-sided Tet10 / a Tet4, sum_a X_a (dN_a/dX)^T = I and det J = 6 V.
  const TetMesh tet10 = test::toTet10(test::twoTets());
  for (const TetMesh* mesh : {&tet10}) {
    const ElementBasis basis(mesh->type);
    Eigen::Matrix3Xd X(3, basis.numNodes());
    for (int a = 0; a < basis.numNodes(); ++a) X.col(a) = mesh->nodes.col(mesh->elements(a, 1));
    Eigen::MatrixXd dN_dX;
    const double det = basis.restGradients(X, Eigen::Vector3d(0.1, 0.2, 0.3), dN_dX);
    EXPECT_NEAR(det, 2.0, 1e-14);  // det J = 6 V, V = 1/3 for the second tet of twoTets
    EXPECT_LT((X * dN_dX - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  }
}

}  // namespace
}  // namespace surgical_sim::core
