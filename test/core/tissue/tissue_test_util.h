#pragma once

// Hand-built meshes and generic physics checks shared by the tissue tests (no core/mesh use).

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/corotational_law.h"
#include "surgical_sim/core/tissue/material.h"
#include "surgical_sim/core/tissue/st_venant_kirchhoff_law.h"
#include "surgical_sim/core/tissue/stable_neo_hookean_law.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core::test {

inline Material testMaterial(double nu = 0.3) { return Material::create(1.0e4, nu, 1000.0); }

/// The hyperelastic law of a model name: "corotational", "svk", otherwise "neo_hookean".
inline std::unique_ptr<HyperelasticLaw> makeLaw(const std::string& name, const Material& m) {
  if (name == "corotational") return std::make_unique<CorotationalLaw>(m);
  if (name == "svk") return std::make_unique<StVenantKirchhoffLaw>(m);
  return std::make_unique<StableNeoHookeanLaw>(m);
}

/// A law on Tet4 or Tet10 elements, the parameter of tests over every FeModel.
struct LawCase {
  std::string law;
  bool tet10;
};

inline std::string lawCaseName(const ::testing::TestParamInfo<LawCase>& info) {
  return info.param.law + (info.param.tet10 ? "_tet10" : "_tet4");
}

/// Every law on Tet4 and on Tet10.
inline auto allLawCases() {
  return ::testing::Values(LawCase{"corotational", false}, LawCase{"svk", false},
                           LawCase{"neo_hookean", false}, LawCase{"corotational", true},
                           LawCase{"svk", true}, LawCase{"neo_hookean", true});
}

/// Swaps corners 2 and 3 of negatively oriented Tet4 elements.
inline void orientTet4(TetMesh& mesh) {
  for (int e = 0; e < mesh.numElements(); ++e) {
    const Eigen::Vector3d p0 = mesh.nodes.col(mesh.elements(0, e));
    const Eigen::Vector3d p1 = mesh.nodes.col(mesh.elements(1, e));
    const Eigen::Vector3d p2 = mesh.nodes.col(mesh.elements(2, e));
    const Eigen::Vector3d p3 = mesh.nodes.col(mesh.elements(3, e));
    if ((p1 - p0).dot((p2 - p0).cross(p3 - p0)) < 0.0) {
      std::swap(mesh.elements(2, e), mesh.elements(3, e));
    }
  }
}

/// Unit right tet (0,0,0), (1,0,0), (0,1,0), (0,0,1) scaled by `size` [m]; V = size^3 / 6.
inline TetMesh singleTet(double size = 1.0) {
  TetMesh mesh;
  mesh.type = ElementType::Tet4;
  mesh.nodes.resize(3, 4);
  mesh.nodes << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  mesh.nodes *= size;
  mesh.elements.resize(4, 1);
  mesh.elements << 0, 1, 2, 3;
  return mesh;
}

/// Two tets sharing the face (1, 2, 3).
inline TetMesh twoTets() {
  TetMesh mesh;
  mesh.type = ElementType::Tet4;
  mesh.nodes.resize(3, 5);
  mesh.nodes << 0, 1, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 0, 1, 1;
  mesh.elements.resize(4, 2);
  mesh.elements << 0, 1, 1, 2, 2, 3, 3, 4;
  orientTet4(mesh);
  return mesh;
}

/// Cube [0, size]^3 split into 6 tets around the diagonal 0-7 (Kuhn triangulation).
inline TetMesh cubeSixTets(double size = 1.0) {
  TetMesh mesh;
  mesh.type = ElementType::Tet4;
  mesh.nodes.resize(3, 8);
  for (int v = 0; v < 8; ++v) {
    mesh.nodes.col(v) = size * Eigen::Vector3d(v & 1, (v >> 1) & 1, (v >> 2) & 1);
  }
  std::array<int, 3> axes = {0, 1, 2};
  mesh.elements.resize(4, 6);
  int e = 0;
  do {
    const int a = 1 << axes[0];
    const int b = a | (1 << axes[1]);
    mesh.elements.col(e++) << 0, a, b, 7;
  } while (std::next_permutation(axes.begin(), axes.end()));
  orientTet4(mesh);
  return mesh;
}

/// Cube [0, cells h]^3 of cells^3 Kuhn-triangulated cubes (6 tets each) with every node moved by a
/// uniform random offset of up to `jitter` [m] per coordinate and the nodes numbered in random
/// order; elements re-oriented positively.
inline TetMesh jitteredLattice(int cells, double h, double jitter, std::mt19937& rng) {
  const int side = cells + 1;
  std::vector<int> label(static_cast<size_t>(side * side * side));
  for (size_t i = 0; i < label.size(); ++i) label[i] = static_cast<int>(i);
  std::shuffle(label.begin(), label.end(), rng);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  TetMesh mesh;
  mesh.type = ElementType::Tet4;
  mesh.nodes.resize(3, static_cast<Eigen::Index>(label.size()));
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i)
        mesh.nodes.col(label[static_cast<size_t>((k * side + j) * side + i)]) =
            h * Eigen::Vector3d(i, j, k) + Eigen::Vector3d(u(rng), u(rng), u(rng));
  const TetMesh cube = cubeSixTets();
  mesh.elements.resize(4, 6 * cells * cells * cells);
  int e = 0;
  for (int k = 0; k < cells; ++k)
    for (int j = 0; j < cells; ++j)
      for (int i = 0; i < cells; ++i)
        for (int t = 0; t < 6; ++t, ++e)
          for (int a = 0; a < 4; ++a) {
            const int v = cube.elements(a, t);
            const int grid = ((k + (v >> 2 & 1)) * side + j + (v >> 1 & 1)) * side + i + (v & 1);
            mesh.elements(a, e) = label[static_cast<size_t>(grid)];
          }
  orientTet4(mesh);
  return mesh;
}

/// Tet10 mesh from a Tet4 mesh by adding straight mid-edge nodes (Gmsh order).
inline TetMesh toTet10(const TetMesh& tet4) {
  constexpr int kPairs[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
  TetMesh mesh;
  mesh.type = ElementType::Tet10;
  std::vector<Eigen::Vector3d> nodes;
  for (int v = 0; v < tet4.numNodes(); ++v) nodes.push_back(tet4.nodes.col(v));
  std::map<std::pair<int, int>, int> mid;
  mesh.elements.resize(10, tet4.numElements());
  for (int e = 0; e < tet4.numElements(); ++e) {
    for (int a = 0; a < 4; ++a) mesh.elements(a, e) = tet4.elements(a, e);
    for (int m = 0; m < 6; ++m) {
      const int i = tet4.elements(kPairs[m][0], e);
      const int j = tet4.elements(kPairs[m][1], e);
      const auto key = std::make_pair(std::min(i, j), std::max(i, j));
      auto it = mid.find(key);
      if (it == mid.end()) {
        it = mid.emplace(key, static_cast<int>(nodes.size())).first;
        nodes.push_back(0.5 * (nodes[i] + nodes[j]));
      }
      mesh.elements(4 + m, e) = it->second;
    }
  }
  mesh.nodes.resize(3, static_cast<Eigen::Index>(nodes.size()));
  for (size_t v = 0; v < nodes.size(); ++v) mesh.nodes.col(static_cast<Eigen::Index>(v)) = nodes[v];
  return mesh;
}

inline Eigen::VectorXd flatten(const Eigen::Matrix3Xd& nodes) {
  return Eigen::Map<const Eigen::VectorXd>(nodes.data(), nodes.size());
}

/// x = rest + uniform random perturbation of amplitude `amplitude` [m] per coordinate.
inline Eigen::VectorXd perturbed(const Eigen::VectorXd& rest, double amplitude, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  Eigen::VectorXd x = rest;
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) += u(rng);
  return x;
}

/// x_i = A X_i + t applied to every node.
inline Eigen::VectorXd affine(const Eigen::VectorXd& rest, const Eigen::Matrix3d& A,
                              const Eigen::Vector3d& t = Eigen::Vector3d::Zero()) {
  Eigen::VectorXd x(rest.size());
  for (Eigen::Index i = 0; i < rest.size() / 3; ++i)
    x.segment<3>(3 * i) = A * rest.segment<3>(3 * i) + t;
  return x;
}

inline Eigen::VectorXd force(const TissueModel& model, const Eigen::VectorXd& x) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  model.addInternalForce(x, f);
  return f;
}

inline Eigen::MatrixXd denseStiffness(const TissueModel& model, const Eigen::VectorXd& x,
                                      TangentMode mode) {
  Eigen::SparseMatrix<double> K = model.stiffnessPattern();
  model.assembleStiffness(x, mode, K);
  return Eigen::MatrixXd(K);
}

inline double relativeError(const Eigen::MatrixXd& approx, const Eigen::MatrixXd& ref) {
  return (approx - ref).norm() / ref.norm();
}

/// Central differences of the energy equal minus the force.
inline void expectForceIsMinusEnergyGradient(const TissueModel& model, const Eigen::VectorXd& x,
                                             double length_scale, double tol = 1e-6) {
  const double h = 1e-6 * length_scale;
  Eigen::VectorXd fd(x.size());
  Eigen::VectorXd xp = x;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    xp(i) = x(i) + h;
    const double ep = model.energy(xp);
    xp(i) = x(i) - h;
    const double em = model.energy(xp);
    xp(i) = x(i);
    fd(i) = -(ep - em) / (2.0 * h);
  }
  EXPECT_LT(relativeError(force(model, x), fd), tol) << model.name();
}

/// Central differences of the force equal -K (Exact mode).
inline void expectStiffnessIsMinusForceJacobian(const TissueModel& model, const Eigen::VectorXd& x,
                                                double length_scale, double tol = 1e-6) {
  const double h = 1e-6 * length_scale;
  Eigen::MatrixXd fd(x.size(), x.size());
  Eigen::VectorXd xp = x;
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    xp(j) = x(j) + h;
    const Eigen::VectorXd fp = force(model, xp);
    xp(j) = x(j) - h;
    const Eigen::VectorXd fm = force(model, xp);
    xp(j) = x(j);
    fd.col(j) = -(fp - fm) / (2.0 * h);
  }
  const Eigen::MatrixXd K = denseStiffness(model, x, TangentMode::Exact);
  EXPECT_LT(relativeError(K, fd), tol) << model.name();
  EXPECT_LT((K - K.transpose()).norm(), 1e-12 * K.norm()) << model.name();
}

/// applyStiffness(v) equals the assembled K times v, in both modes.
inline void expectApplyMatchesAssembled(const TissueModel& model, const Eigen::VectorXd& x,
                                        std::mt19937& rng) {
  const Eigen::VectorXd v = perturbed(Eigen::VectorXd::Zero(x.size()), 1.0, rng);
  for (TangentMode mode : {TangentMode::Exact, TangentMode::ProjectedSpd}) {
    const Eigen::VectorXd Kv = denseStiffness(model, x, mode) * v;
    Eigen::VectorXd y;
    model.applyStiffness(x, mode, v, y);
    EXPECT_LT(relativeError(y, Kv), 1e-13) << model.name();
  }
}

/// The 6 rigid modes (3 translations, 3 infinitesimal rotations) lie in the null space of K at
/// rest, in both modes; and K is not zero.
inline void expectRigidModesInNullSpace(const TissueModel& model) {
  const Eigen::VectorXd& X = model.restPositions();
  const int n = model.numNodes();
  for (TangentMode mode : {TangentMode::Exact, TangentMode::ProjectedSpd}) {
    const Eigen::MatrixXd K = denseStiffness(model, X, mode);
    ASSERT_GT(K.norm(), 0.0);
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::VectorXd t = Eigen::VectorXd::Zero(3 * n);
      Eigen::VectorXd r(3 * n);
      for (int i = 0; i < n; ++i) {
        t(3 * i + axis) = 1.0;
        r.segment<3>(3 * i) = Eigen::Vector3d::Unit(axis).cross(X.segment<3>(3 * i));
      }
      EXPECT_LT((K * t).norm(), 1e-10 * K.norm() * t.norm()) << model.name();
      EXPECT_LT((K * r).norm(), 1e-10 * K.norm() * r.norm()) << model.name();
    }
  }
}

/// A finite rotation (plus translation) of the rest shape produces zero force and energy.
inline void expectRotationIsForceFree(const TissueModel& model) {
  const Eigen::VectorXd& X = model.restPositions();
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  const Eigen::VectorXd x = affine(X, R, Eigen::Vector3d(0.4, -2.0, 1.5));
  // Reference scale: the force of a 10 % uniform stretch.
  const double ref = force(model, affine(X, 1.1 * Eigen::Matrix3d::Identity())).norm();
  ASSERT_GT(ref, 0.0);
  EXPECT_LT(force(model, x).norm(), 1e-10 * ref) << model.name();
  EXPECT_LT(std::abs(model.energy(x)),
            1e-10 * model.energy(affine(X, 1.1 * Eigen::Matrix3d::Identity())))
      << model.name();
}

/// ProjectedSpd K is symmetric positive semi-definite at x.
inline void expectProjectedIsPsd(const TissueModel& model, const Eigen::VectorXd& x) {
  const Eigen::MatrixXd K = denseStiffness(model, x, TangentMode::ProjectedSpd);
  EXPECT_LT((K - K.transpose()).norm(), 1e-12 * K.norm()) << model.name();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (K + K.transpose()));
  EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-10 * eig.eigenvalues().maxCoeff()) << model.name();
}

/// Smallest eigenvalue of the Exact K (to confirm a test configuration really is indefinite).
inline double exactMinEigenvalueRatio(const TissueModel& model, const Eigen::VectorXd& x) {
  const Eigen::MatrixXd K = denseStiffness(model, x, TangentMode::Exact);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (K + K.transpose()));
  return eig.eigenvalues().minCoeff() / eig.eigenvalues().maxCoeff();
}

/// Compressed (50 % along z) and partially inverted (node 0 pushed through the opposite face of
/// its first element) configuration of a Tet4-cornered mesh.
inline Eigen::VectorXd compressedInverted(const TetMesh& mesh) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
  A(2, 2) = 0.5;
  A(0, 1) = 0.2;
  Eigen::VectorXd x = affine(flatten(mesh.nodes), A);
  const int n0 = mesh.elements(0, 0);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int a = 1; a < 4; ++a) centroid += x.segment<3>(3 * mesh.elements(a, 0)) / 3.0;
  x.segment<3>(3 * n0) += 1.7 * (centroid - x.segment<3>(3 * n0));
  return x;
}

}  // namespace surgical_sim::core::test
