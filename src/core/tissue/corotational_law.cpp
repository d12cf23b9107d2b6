#include "surgical_sim/core/tissue/corotational_law.h"

#include <cmath>

namespace surgical_sim::core {
namespace {

// Column-major vectorisation of a 3 x 3 matrix.
Eigen::Matrix<double, 9, 1> vec(const Eigen::Matrix3d& A) {
  return Eigen::Map<const Eigen::Matrix<double, 9, 1>>(A.data());
}

// Lower bound on |s_i + s_j| in the dR/dF term [-] (sign kept).
constexpr double kMinPairSum = 1e-8;

constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};

// tr(R^T F - I) = s0 + s1 + s2 - 3.
double traceStrain(const Eigen::Matrix3d& F, const Eigen::Matrix3d& R) {
  return R.cwiseProduct(F).sum() - 3.0;
}

}  // namespace

CorotationalLaw::CorotationalLaw(const Material& material) {
  const Material m = Material::validated(material);
  mu_ = m.mu();
  lambda_ = m.lambda();
}

double CorotationalLaw::energyDensity(const Eigen::Matrix3d& F) const {
  return energyDensity(F, computeSignedRotation(F));
}

double CorotationalLaw::energyDensity(const Eigen::Matrix3d& F, const Eigen::Matrix3d& R) const {
  const double trace_strain = traceStrain(F, R);
  return mu_ * (F - R).squaredNorm() + 0.5 * lambda_ * trace_strain * trace_strain;
}

Eigen::Matrix3d CorotationalLaw::firstPiola(const Eigen::Matrix3d& F) const {
  return stress(F, computeSignedRotation(F));
}

Matrix9d CorotationalLaw::firstPiolaDerivative(const Eigen::Matrix3d& F) const {
  const SignedSvd svd = computeSignedSvd(F);
  return exactTangent(svd, svd.U * svd.V.transpose());
}

Matrix9d CorotationalLaw::projectedFirstPiolaDerivative(const Eigen::Matrix3d& F) const {
  return projectedTangent(computeSignedRotation(F));
}

StressAndTangent CorotationalLaw::stressAndTangent(const Eigen::Matrix3d& F,
                                                   TangentMode mode) const {
  if (mode == TangentMode::Exact) {
    const SignedSvd svd = computeSignedSvd(F);
    const Eigen::Matrix3d R = svd.U * svd.V.transpose();
    return {stress(F, R), exactTangent(svd, R)};
  }
  const Eigen::Matrix3d R = computeSignedRotation(F);
  return {stress(F, R), projectedTangent(R)};
}

std::optional<RotatedLinearStressAndTangent> CorotationalLaw::rotatedLinearStressAndTangent(
    const Eigen::Matrix3d& F) const {
  const Eigen::Matrix3d R = computeSignedRotation(F);
  return RotatedLinearStressAndTangent{stress(F, R), R, mu_, lambda_, energyDensity(F, R)};
}

Eigen::Matrix3d CorotationalLaw::stress(const Eigen::Matrix3d& F, const Eigen::Matrix3d& R) const {
  return 2.0 * mu_ * (F - R) + (lambda_ * traceStrain(F, R)) * R;
}

Matrix9d CorotationalLaw::exactTangent(const SignedSvd& svd, const Eigen::Matrix3d& R) const {
  const Eigen::Matrix<double, 9, 1> r = vec(R);
  const double c = lambda_ * (svd.s.sum() - 3.0) - 2.0 * mu_;
  Matrix9d dPdF = 2.0 * mu_ * Matrix9d::Identity();
  dPdF.noalias() += lambda_ * r * r.transpose();
  for (const auto& pair : kPairs) {
    const int i = pair[0];
    const int j = pair[1];
    double sum = svd.s(i) + svd.s(j);
    if (std::abs(sum) < kMinPairSum) sum = sum < 0.0 ? -kMinPairSum : kMinPairSum;
    const Eigen::Matrix3d Q =
        svd.U.col(i) * svd.V.col(j).transpose() - svd.U.col(j) * svd.V.col(i).transpose();
    const Eigen::Matrix<double, 9, 1> q = vec(Q);
    dPdF.noalias() += (c / sum) * q * q.transpose();
  }
  return dPdF;
}

Matrix9d CorotationalLaw::projectedTangent(const Eigen::Matrix3d& R) const {
  const Eigen::Matrix<double, 9, 1> r = vec(R);
  // R sym(R^T dF) = dF - sum_{i<j} k_ij <k_ij, dF>, k_ij = vec(R (e_i e_j^T - e_j e_i^T)) / sqrt 2.
  Matrix9d dPdF = 2.0 * mu_ * Matrix9d::Identity();
  dPdF.noalias() += lambda_ * r * r.transpose();
  for (const auto& pair : kPairs) {
    const int i = pair[0];
    const int j = pair[1];
    Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
    K.col(j) = R.col(i);
    K.col(i) = -R.col(j);
    const Eigen::Matrix<double, 9, 1> k = vec(K);
    dPdF.noalias() -= mu_ * k * k.transpose();  // 2 mu * (1/sqrt2)^2
  }
  return dPdF;
}

}  // namespace surgical_sim::core
