#include "surgical_sim/core/tissue/stable_neo_hookean_law.h"

#include <Eigen/LU>

#include "surgical_sim/core/tissue/cofactor.h"
#include "surgical_sim/core/tissue/psd_projection.h"

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
  Matrix9d dPdF = firstPiolaDerivative(F);
  projectToPsd(dPdF);
  return dPdF;
}

}  // namespace surgical_sim::core
