#pragma once

#include "surgical_sim/core/tissue/hyperelastic_law.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {

/// St Venant-Kirchhoff: E = (F^T F - I) / 2, psi = (lambda / 2) tr(E)^2 + mu tr(E^2),
/// S = lambda tr(E) I + 2 mu E, P = F S (Chendeb eqs 3.16-3.17; the EMS model is the same law).
/// Exact tangent dP = dF S + F dS with dS = lambda tr(dE) I + 2 mu dE, dE = sym(F^T dF).
/// Projected tangent: eigenvalues of the 9 x 9 exact tangent clamped at 0.
/// Note: SVK softens under compression (uniaxial force peaks at stretch 1/sqrt(3)) and is not
/// restoring for inverted elements.
class StVenantKirchhoffLaw final : public HyperelasticLaw {
 public:
  /// @throws std::invalid_argument if the material is out of range (see Material::create).
  explicit StVenantKirchhoffLaw(const Material& material);

  std::string name() const override { return "svk"; }
  double energyDensity(const Eigen::Matrix3d& F) const override;
  Eigen::Matrix3d firstPiola(const Eigen::Matrix3d& F) const override;
  Matrix9d firstPiolaDerivative(const Eigen::Matrix3d& F) const override;
  Matrix9d projectedFirstPiolaDerivative(const Eigen::Matrix3d& F) const override;

 private:
  double mu_;      ///< shear modulus [Pa]
  double lambda_;  ///< Lame's first parameter [Pa]
};

}  // namespace surgical_sim::core
