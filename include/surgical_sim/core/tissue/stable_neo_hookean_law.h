#pragma once

#include "surgical_sim/core/tissue/hyperelastic_law.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {

/// Stable Neo-Hookean (Smith, de Goes, Kim 2018, in the simplified form of Kim & Eberle's
/// "Dynamic Deformables" course):
///   psi(F) = (mu / 2) (I_C - 3) - mu (J - 1) + (lambda' / 2) (J - 1)^2,  lambda' = lambda + mu,
/// with I_C = ||F||_F^2 and J = det F. No log(J): finite for J <= 0 (inverted elements).
///   P(F) = mu F + (lambda' (J - 1) - mu) cof(F),   cof(F) = dJ/dF = J F^{-T},
/// so P(I) = 0 and, because of the shift lambda' = lambda + mu, the linearisation at F = I is
/// exactly linear elasticity with the material's (mu, lambda): dP = 2 mu sym(dF) + lambda tr(dF) I.
/// Exact tangent: mu I + lambda' vec(cof) vec(cof)^T + (lambda' (J - 1) - mu) d2J/dF2.
/// Projected tangent: eigenvalues of the 9 x 9 exact tangent clamped at 0, from its closed-form
/// eigensystem in the frame of the signed SVD of F (a 3 x 3 scaling block and three twist / flip
/// pairs, as in Smith et al.), without a 9 x 9 eigensolver.
class StableNeoHookeanLaw final : public HyperelasticLaw {
 public:
  /// @throws std::invalid_argument if the material is out of range (see Material::create).
  explicit StableNeoHookeanLaw(const Material& material);

  std::string name() const override { return "neo_hookean"; }
  double energyDensity(const Eigen::Matrix3d& F) const override;
  Eigen::Matrix3d firstPiola(const Eigen::Matrix3d& F) const override;
  Matrix9d firstPiolaDerivative(const Eigen::Matrix3d& F) const override;
  Matrix9d projectedFirstPiolaDerivative(const Eigen::Matrix3d& F) const override;

 private:
  double mu_;            ///< shear modulus [Pa]
  double lambda_shift_;  ///< lambda' = lambda + mu [Pa]
};

}  // namespace surgical_sim::core
