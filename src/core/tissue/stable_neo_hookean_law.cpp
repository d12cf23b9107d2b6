#include "surgical_sim/core/tissue/stable_neo_hookean_law.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>

#include "surgical_sim/core/tissue/cofactor.h"
#include "surgical_sim/core/tissue/signed_svd.h"

namespace surgical_sim::core {
namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d S;
  S << 0.0, -a(2), a(1), a(2), 0.0, -a(0), -a(1), a(0), 0.0;
  return S;
}

}  // namespace

StableNeoHookeanLaw::StableNeoHookeanLaw(const Material& material) {
  const Material m = Material::validated(material);
  mu_ = m.mu();
  lambda_shift_ = m.lambda() + m.mu();
}

double StableNeoHookeanLaw::energyDensity(const Eigen::Matrix3d& F) const {
  const double J = F.determinant();
  return 0.5 * mu_ * (F.squaredNorm() - 3.0) - mu_ * (J - 1.0) +
         0.5 * lambda_shift_ * (J - 1.0) * (J - 1.0);
}

Eigen::Matrix3d StableNeoHookeanLaw::firstPiola(const Eigen::Matrix3d& F) const {
  const double J = F.determinant();
  return mu_ * F + (lambda_shift_ * (J - 1.0) - mu_) * cofactor(F);
}

Matrix9d StableNeoHookeanLaw::firstPiolaDerivative(const Eigen::Matrix3d& F) const {
  const double J = F.determinant();
  const Eigen::Matrix3d cof = cofactor(F);
  const Eigen::Map<const Eigen::Matrix<double, 9, 1>> g(cof.data());
  Matrix9d dPdF = mu_ * Matrix9d::Identity();
  dPdF.noalias() += lambda_shift_ * g * g.transpose();
  // Hessian of J: block (k, l) = d cof.col(k) / d F.col(l).
  const double s = lambda_shift_ * (J - 1.0) - mu_;
  const Eigen::Matrix3d S0 = s * skew(F.col(0));
  const Eigen::Matrix3d S1 = s * skew(F.col(1));
  const Eigen::Matrix3d S2 = s * skew(F.col(2));
  dPdF.block<3, 3>(0, 3) -= S2;
  dPdF.block<3, 3>(0, 6) += S1;
  dPdF.block<3, 3>(3, 0) += S2;
  dPdF.block<3, 3>(3, 6) -= S0;
  dPdF.block<3, 3>(6, 0) -= S1;
  dPdF.block<3, 3>(6, 3) += S0;
  return dPdF;
}

Matrix9d StableNeoHookeanLaw::projectedFirstPiolaDerivative(const Eigen::Matrix3d& F) const {
  // In the frame of the signed SVD F = U diag(s) V^T the tangent splits into a 3 x 3 block on the
  // diagonal entries of dF (scaling) and three 2 x 2 blocks on the pairs (dF_ij, dF_ji) (twist,
  // flip), with c = (s1 s2, s0 s2, s0 s1) = cof(diag(s)) and t = lambda' (J - 1) - mu:
  //   A = mu I + lambda' c c^T + t [[0, s2, s1], [s2, 0, s0], [s1, s0, 0]],
  //   [[mu, -t s_k], [-t s_k, mu]] with eigenvalues mu -+ t s_k, eigenvectors (1, +-1) / sqrt 2.
  // Every eigenvalue clamped at 0, the eigenvectors rotated back: vec(U E V^T).
  const SignedSvd svd = computeSignedSvd(F);
  const Eigen::Vector3d& sv = svd.s;
  const double J = sv.prod();
  const double t = lambda_shift_ * (J - 1.0) - mu_;
  const Eigen::Vector3d c(sv(1) * sv(2), sv(0) * sv(2), sv(0) * sv(1));
  Eigen::Matrix3d A = mu_ * Eigen::Matrix3d::Identity() + lambda_shift_ * c * c.transpose();
  A(0, 1) += t * sv(2);
  A(1, 0) += t * sv(2);
  A(0, 2) += t * sv(1);
  A(2, 0) += t * sv(1);
  A(1, 2) += t * sv(0);
  A(2, 1) += t * sv(0);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> scaling;
  scaling.computeDirect(A);
  Matrix9d dPdF = Matrix9d::Zero();
  const auto add = [&](double eigenvalue, const Eigen::Matrix3d& E) {
    if (!(eigenvalue > 0.0)) return;
    const Eigen::Matrix3d Q = svd.U * E * svd.V.transpose();
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> q(Q.data());
    dPdF.noalias() += eigenvalue * q * q.transpose();
  };
  for (int k = 0; k < 3; ++k) {
    add(scaling.eigenvalues()(k), scaling.eigenvectors().col(k).asDiagonal().toDenseMatrix());
  }
  constexpr int kPairs[3][3] = {{1, 2, 0}, {0, 2, 1}, {0, 1, 2}};  // (i, j, k): the pair and s_k
  const double inv_sqrt2 = 1.0 / std::sqrt(2.0);
  for (const auto& pair : kPairs) {
    Eigen::Matrix3d twist = Eigen::Matrix3d::Zero();
    twist(pair[0], pair[1]) = inv_sqrt2;
    Eigen::Matrix3d flip = twist;
    twist(pair[1], pair[0]) = -inv_sqrt2;
    flip(pair[1], pair[0]) = inv_sqrt2;
    add(mu_ + t * sv(pair[2]), twist);
    add(mu_ - t * sv(pair[2]), flip);
  }
  return dPdF;
}

}  // namespace surgical_sim::core
