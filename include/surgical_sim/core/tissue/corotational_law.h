#pragma once

#include "surgical_sim/core/tissue/hyperelastic_law.h"
#include "surgical_sim/core/tissue/material.h"
#include "surgical_sim/core/tissue/signed_svd.h"

namespace surgical_sim::core {

/// Corotational linear elasticity:
///   psi(F) = mu ||F - R||_F^2 + (lambda / 2) tr(R^T F - I)^2,
///   P(F)   = 2 mu (F - R) + lambda tr(R^T F - I) R,
/// with R = U V^T the rotation of the signed SVD F = U diag(s) V^T (see computeSignedSvd), so the
/// law stays defined and restoring for inverted elements (det F <= 0). Energy, stress and the
/// projected tangent only need R (||F - R||^2 = sum (s_i - 1)^2, tr(R^T F) = tr S), which
/// computeSignedRotation gives without the SVD; the exact tangent uses the full SVD.
///
/// Exact tangent (dR included): with q_ij = vec(u_i v_j^T - u_j v_i^T) (u, v columns of U, V),
///   dP/dF = 2 mu I + lambda r r^T + (lambda (tr S - 3) - 2 mu) sum_{i<j} q_ij q_ij^T / (s_i +
///   s_j),
/// r = vec(R), tr S = s0 + s1 + s2; |s_i + s_j| is clamped below at 1e-8 (sign kept).
/// Projected tangent: the fixed-R tangent dP = R (2 mu sym(R^T dF) + lambda tr(R^T dF) I), the
/// classic R K0 R^T, which is positive semi-definite.
class CorotationalLaw final : public HyperelasticLaw {
 public:
  /// @throws std::invalid_argument if the material is out of range (see Material::create).
  explicit CorotationalLaw(const Material& material);

  std::string name() const override { return "corotational"; }
  double energyDensity(const Eigen::Matrix3d& F) const override;
  Eigen::Matrix3d firstPiola(const Eigen::Matrix3d& F) const override;
  Matrix9d firstPiolaDerivative(const Eigen::Matrix3d& F) const override;
  Matrix9d projectedFirstPiolaDerivative(const Eigen::Matrix3d& F) const override;
  /// One rotation (ProjectedSpd) or one SVD (Exact) for both.
  StressAndTangent stressAndTangent(const Eigen::Matrix3d& F, TangentMode mode) const override;
  /// P and the projected tangent (R, mu, lambda) from one rotation.
  std::optional<RotatedLinearStressAndTangent> rotatedLinearStressAndTangent(
      const Eigen::Matrix3d& F) const override;

 private:
  /// psi(F) for the rotation R of F [J/m^3].
  double energyDensity(const Eigen::Matrix3d& F, const Eigen::Matrix3d& R) const;
  /// P(F) for the rotation R of F.
  Eigen::Matrix3d stress(const Eigen::Matrix3d& F, const Eigen::Matrix3d& R) const;
  /// Exact dP/dF from the signed SVD of F and R = U V^T.
  Matrix9d exactTangent(const SignedSvd& svd, const Eigen::Matrix3d& R) const;
  /// Fixed-R tangent R K0 R^T for the rotation R of F.
  Matrix9d projectedTangent(const Eigen::Matrix3d& R) const;

  double mu_;      ///< shear modulus [Pa]
  double lambda_;  ///< Lame's first parameter [Pa]
};

}  // namespace surgical_sim::core
