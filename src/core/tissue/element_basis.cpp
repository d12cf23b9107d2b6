#include "surgical_sim/core/tissue/element_basis.h"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <vector>

namespace surgical_sim::core {
namespace {

// Corner pairs of the Tet10 mid-edge nodes 4..9 (Gmsh order).
constexpr std::array<std::array<int, 2>, 6> kEdgeCorners = {
    {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}}};

// Gradients of the barycentric coordinates L0..L3 with respect to (xi, eta, zeta).
Eigen::Matrix<double, 4, 3> barycentricGradients() {
  Eigen::Matrix<double, 4, 3> g;
  g << -1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  return g;
}

Eigen::Vector4d barycentric(const Eigen::Vector3d& xi) {
  return Eigen::Vector4d(1.0 - xi.sum(), xi(0), xi(1), xi(2));
}

// Appends all distinct permutations of barycentric coordinates `lambda` with weight w.
void addOrbit(const Eigen::Vector4d& lambda, double w, std::vector<Eigen::Vector3d>& points,
              std::vector<double>& weights) {
  std::array<int, 4> perm = {0, 1, 2, 3};
  std::vector<Eigen::Vector4d> seen;
  do {
    Eigen::Vector4d p(lambda(perm[0]), lambda(perm[1]), lambda(perm[2]), lambda(perm[3]));
    bool duplicate = false;
    for (const auto& s : seen) duplicate = duplicate || (s - p).cwiseAbs().maxCoeff() < 1e-14;
    if (duplicate) continue;
    seen.push_back(p);
    points.emplace_back(p(1), p(2), p(3));
    weights.push_back(w);
  } while (std::next_permutation(perm.begin(), perm.end()));
}

QuadratureRule makeRule(const std::vector<Eigen::Vector3d>& points,
                        const std::vector<double>& weights) {
  QuadratureRule rule;
  rule.points.resize(3, static_cast<Eigen::Index>(points.size()));
  rule.weights.resize(static_cast<Eigen::Index>(weights.size()));
  for (size_t q = 0; q < points.size(); ++q) {
    rule.points.col(static_cast<Eigen::Index>(q)) = points[q];
    rule.weights(static_cast<Eigen::Index>(q)) = weights[q];
  }
  return rule;
}

QuadratureRule centroidRule() { return makeRule({Eigen::Vector3d::Constant(0.25)}, {1.0 / 6.0}); }

// 4-point rule of degree 2 (Keast / Hammer-Stroud), weights 1/24.
QuadratureRule degree2Rule() {
  const double a = 0.1381966011250105;  // (5 - sqrt(5)) / 20
  const double b = 1.0 - 3.0 * a;
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  addOrbit(Eigen::Vector4d(b, a, a, a), 1.0 / 24.0, points, weights);
  return makeRule(points, weights);
}

// 14-point rule of degree 5 with positive weights (Walkington / Keast), weights sum 1/6.
QuadratureRule degree5Rule() {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  const double a1 = 0.0927352503108912;
  addOrbit(Eigen::Vector4d(1.0 - 3.0 * a1, a1, a1, a1), 0.01224884051939366, points, weights);
  const double a2 = 0.3108859192633006;
  addOrbit(Eigen::Vector4d(1.0 - 3.0 * a2, a2, a2, a2), 0.01878132095300264, points, weights);
  const double a3 = 0.0455037041256496;
  addOrbit(Eigen::Vector4d(a3, a3, 0.5 - a3, 0.5 - a3), 0.007091003462846911, points, weights);
  return makeRule(points, weights);
}

}  // namespace

ElementBasis::ElementBasis(ElementType type) : type_(type) {
  if (type_ == ElementType::Tet10) {
    stiffness_rule_ = degree2Rule();
    mass_rule_ = degree5Rule();
  } else {
    stiffness_rule_ = centroidRule();
    mass_rule_ = degree2Rule();
  }
}

Eigen::VectorXd ElementBasis::shapeValues(const Eigen::Vector3d& xi) const {
  const Eigen::Vector4d L = barycentric(xi);
  Eigen::VectorXd N(numNodes());
  if (type_ == ElementType::Tet4) {
    N = L;
    return N;
  }
  for (int a = 0; a < 4; ++a) N(a) = L(a) * (2.0 * L(a) - 1.0);
  for (int m = 0; m < 6; ++m) N(4 + m) = 4.0 * L(kEdgeCorners[m][0]) * L(kEdgeCorners[m][1]);
  return N;
}

Eigen::MatrixXd ElementBasis::shapeGradients(const Eigen::Vector3d& xi) const {
  const Eigen::Matrix<double, 4, 3> dL = barycentricGradients();
  Eigen::MatrixXd dN(numNodes(), 3);
  if (type_ == ElementType::Tet4) {
    dN = dL;
    return dN;
  }
  const Eigen::Vector4d L = barycentric(xi);
  for (int a = 0; a < 4; ++a) dN.row(a) = (4.0 * L(a) - 1.0) * dL.row(a);
  for (int m = 0; m < 6; ++m) {
    const int i = kEdgeCorners[m][0];
    const int j = kEdgeCorners[m][1];
    dN.row(4 + m) = 4.0 * (L(j) * dL.row(i) + L(i) * dL.row(j));
  }
  return dN;
}

double ElementBasis::restGradients(const Eigen::Matrix3Xd& X_e, const Eigen::Vector3d& xi,
                                   Eigen::MatrixXd& dN_dX) const {
  const Eigen::MatrixXd dN_dxi = shapeGradients(xi);
  const Eigen::Matrix3d J = X_e * dN_dxi;  // J(i, j) = dX_i / dxi_j
  const double det = J.determinant();
  if (det != 0.0) dN_dX = dN_dxi * J.inverse();
  return det;
}

}  // namespace surgical_sim::core
