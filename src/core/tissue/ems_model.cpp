#include "surgical_sim/core/tissue/ems_model.h"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>

#include "surgical_sim/core/tissue/block_sparsity.h"
#include "surgical_sim/core/tissue/psd_projection.h"
#include "surgical_sim/core/tissue/tissue_mesh_check.h"

namespace surgical_sim::core {
namespace {

// Edges i = 1..6 of the thesis (0-based here) as (from, to) corners: edge vector x_to - x_from.
constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {2, 3}, {3, 1}};

// G_i: coefficient of l_i^2 in the Gram matrix G = v^T v of the edge vectors v1, v2, v3, from
// G_aa = l_a^2 and G_ab = (l_a^2 + l_b^2 - l_ab^2) / 2 (a != b).
Eigen::Matrix3d gramCoefficient(int i) {
  Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
  if (i < 3) {  // l_i = |v_i|: G_ii and half of every G_ib
    G.row(i).setConstant(0.5);
    G.col(i).setConstant(0.5);
    G(i, i) = 1.0;
  } else {  // l_i = |v_b - v_a| enters G_ab only
    const int a = kEdges[i][0] - 1;
    const int b = kEdges[i][1] - 1;
    G(a, b) = -0.5;
    G(b, a) = -0.5;
  }
  return G;
}

// DL_k (k = 0..2): dL/dm = sum_k DL_k (x) v_k^T, rows = squared edge, columns = corner.
Eigen::Matrix<double, 6, 4> edgeDerivative(int k) {
  Eigen::Matrix<double, 6, 4> D;
  if (k == 0) {
    D << -2, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, -2, 0, 0, 0, 0, 0, 0, 2, 0, -2;
  } else if (k == 1) {
    D << 0, 0, 0, 0, -2, 0, 2, 0, 0, 0, 0, 0, 0, -2, 2, 0, 0, 0, 2, -2, 0, 0, 0, 0;
  } else {
    D << 0, 0, 0, 0, 0, 0, 0, 0, -2, 0, 0, 2, 0, 0, 0, 0, 0, 0, -2, 2, 0, -2, 0, 2;
  }
  return D;
}

}  // namespace

EmsModel::EmsModel(const TetMesh& mesh, const Material& material) {
  const Material mat = Material::validated(material);
  checkTissueMesh(mesh, "ems", /*allow_tet10=*/false);
  const double lambda = mat.lambda();
  const double mu = mat.mu();
  const int n = mesh.numNodes();
  elements_ = mesh.elements;
  rest_positions_ = Eigen::Map<const Eigen::VectorXd>(mesh.nodes.data(), 3 * n);
  lumped_mass_ = Eigen::VectorXd::Zero(3 * n);

  Eigen::Matrix3d G[6];
  for (int i = 0; i < 6; ++i) G[i] = gramCoefficient(i);
  Matrix64d DL[3];
  for (int k = 0; k < 3; ++k) DL[k] = edgeDerivative(k);

  tets_.resize(static_cast<size_t>(mesh.numElements()));
  for (int e = 0; e < mesh.numElements(); ++e) {
    Eigen::Matrix<double, 3, 4> X;
    for (int a = 0; a < 4; ++a) X.col(a) = mesh.nodes.col(elements_(a, e));
    Eigen::Matrix3d V;
    V << X.col(1) - X.col(0), X.col(2) - X.col(0), X.col(3) - X.col(0);
    const Eigen::Matrix3d B = V.inverse();
    Tet& tet = tets_[static_cast<size_t>(e)];
    tet.volume = V.determinant() / 6.0;
    Eigen::Matrix3d C[6];
    Vector6d vtr;
    for (int i = 0; i < 6; ++i) {
      C[i] = B.transpose() * G[i] * B;
      vtr(i) = C[i].trace();
      tet.rest_sq(i) = (X.col(kEdges[i][1]) - X.col(kEdges[i][0])).squaredNorm();
    }
    Matrix6d mtr;
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) mtr(i, j) = (C[i].cwiseProduct(C[j])).sum();  // tr(C_i C_j)
    }
    const Matrix6d mw = (lambda / 8.0) * vtr * vtr.transpose() + (mu / 4.0) * mtr;
    tet.vol_mw = tet.volume * mw;
    for (int k = 0; k < 3; ++k) tet.mwdl[k] = 2.0 * tet.vol_mw * DL[k];
    for (int a = 0; a < 4; ++a) {
      lumped_mass_.segment<3>(3 * elements_(a, e)).array() += mat.density * tet.volume / 4.0;
    }
  }
  setGroups(n, elements_);
}

Eigen::VectorXd EmsModel::bodyForce(const Eigen::Vector3d& a) const {
  Eigen::VectorXd f(lumped_mass_.size());
  for (Eigen::Index i = 0; i < f.size() / 3; ++i) f.segment<3>(3 * i) = lumped_mass_(3 * i) * a;
  return f;
}

EmsModel::Vector6d EmsModel::squaredEdgeDelta(const Eigen::VectorXd& x, int e) const {
  Vector6d dL;
  for (int i = 0; i < 6; ++i) {
    dL(i) = (x.segment<3>(3 * elements_(kEdges[i][1], e)) -
             x.segment<3>(3 * elements_(kEdges[i][0], e)))
                .squaredNorm();
  }
  return dL - tets_[static_cast<size_t>(e)].rest_sq;
}

double EmsModel::energy(const Eigen::VectorXd& x) const {
  double energy = 0.0;
  for (int e = 0; e < elements_.cols(); ++e) {
    const Vector6d dL = squaredEdgeDelta(x, e);
    energy += dL.dot(tets_[static_cast<size_t>(e)].vol_mw * dL);
  }
  return energy;
}

void EmsModel::addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  for (int e = 0; e < elements_.cols(); ++e) {
    const Tet& tet = tets_[static_cast<size_t>(e)];
    const Vector6d dL = squaredEdgeDelta(x, e);
    const Eigen::Vector3d x0 = x.segment<3>(3 * elements_(0, e));
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d v = x.segment<3>(3 * elements_(k + 1, e)) - x0;  // v_k
      const Eigen::Vector4d c = tet.mwdl[k].transpose() * dL;
      for (int node = 0; node < 4; ++node) f.segment<3>(3 * elements_(node, e)) -= c(node) * v;
    }
  }
}

EmsModel::Matrix12d EmsModel::elementStiffness(const Eigen::VectorXd& x, int e,
                                               TangentMode mode) const {
  const Tet& tet = tets_[static_cast<size_t>(e)];
  const Vector6d dL = squaredEdgeDelta(x, e);
  const Vector6d w = 2.0 * tet.vol_mw * dL;                               // dW/dL
  Eigen::Matrix<double, 6, 12> J = Eigen::Matrix<double, 6, 12>::Zero();  // dL/dx
  Matrix12d H = Matrix12d::Zero();
  for (int i = 0; i < 6; ++i) {
    const int a = kEdges[i][0];
    const int b = kEdges[i][1];
    const Eigen::Vector3d edge =
        x.segment<3>(3 * elements_(b, e)) - x.segment<3>(3 * elements_(a, e));
    J.block<1, 3>(i, 3 * b) = 2.0 * edge.transpose();
    J.block<1, 3>(i, 3 * a) = -2.0 * edge.transpose();
    // w_i d2L_i/dx2 = 2 w_i [I -I; -I I] on the corners (a, b).
    const double s = 2.0 * w(i);
    H.block<3, 3>(3 * a, 3 * a).diagonal().array() += s;
    H.block<3, 3>(3 * b, 3 * b).diagonal().array() += s;
    H.block<3, 3>(3 * a, 3 * b).diagonal().array() -= s;
    H.block<3, 3>(3 * b, 3 * a).diagonal().array() -= s;
  }
  H.noalias() += 2.0 * J.transpose() * tet.vol_mw * J;
  if (mode == TangentMode::ProjectedSpd) projectToPsd(H);
  return H;
}

void EmsModel::addGroupStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                                 double* values) const {
  if (f != nullptr) addInternalForce(x, *f);
  for (int e = 0; e < elements_.cols(); ++e) scatterGroup(e, elementStiffness(x, e, mode), values);
}

void EmsModel::applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                              Eigen::VectorXd& y) const {
  y.setZero(rest_positions_.size());
  for (int e = 0; e < elements_.cols(); ++e) {
    Eigen::Matrix<double, 12, 1> ve;
    for (int a = 0; a < 4; ++a) ve.segment<3>(3 * a) = v.segment<3>(3 * elements_(a, e));
    const Eigen::Matrix<double, 12, 1> ye = elementStiffness(x, e, mode) * ve;
    for (int a = 0; a < 4; ++a) y.segment<3>(3 * elements_(a, e)) += ye.segment<3>(3 * a);
  }
}

}  // namespace surgical_sim::core
