#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// 9 x 9 tangent dP/dF [Pa]. Matrices are vectorised column-major: vec(F)[i + 3 j] = F(i, j), and
/// dPdF(i + 3 j, k + 3 l) = dP_ij / dF_kl.
using Matrix9d = Eigen::Matrix<double, 9, 9>;

/// First Piola-Kirchhoff stress and tangent at one F (HyperelasticLaw::stressAndTangent).
struct StressAndTangent {
  Eigen::Matrix3d P;  ///< first Piola-Kirchhoff stress [Pa]
  Matrix9d dPdF;      ///< tangent dP/dF of the requested TangentMode [Pa]
};

/// Stress and a projected tangent that is a rotated isotropic linear tensor,
///   dP = R (2 mu sym(R^T dF) + lambda tr(R^T dF) I),
/// in compact form (HyperelasticLaw::rotatedLinearStressAndTangent).
struct RotatedLinearStressAndTangent {
  Eigen::Matrix3d P;      ///< first Piola-Kirchhoff stress [Pa]
  Eigen::Matrix3d R;      ///< rotation of the tangent
  double mu;              ///< shear modulus of the tangent [Pa]
  double lambda;          ///< Lame's first parameter of the tangent [Pa]
  double energy_density;  ///< psi(F) [J/m^3], equal to HyperelasticLaw::energyDensity(F)
};

/// An isotropic hyperelastic constitutive law psi(F), evaluated per quadrature point.
/// F is the deformation gradient dx/dX [-]; all methods are allocation-free and thread-safe.
class HyperelasticLaw {
 public:
  virtual ~HyperelasticLaw() = default;

  /// Short identifier used as the tissue model name ("corotational", "svk", "neo_hookean").
  virtual std::string name() const = 0;

  /// Strain energy density psi(F) [J/m^3] (per unit rest volume).
  virtual double energyDensity(const Eigen::Matrix3d& F) const = 0;
  /// First Piola-Kirchhoff stress P = dpsi/dF [Pa], 3 x 3.
  virtual Eigen::Matrix3d firstPiola(const Eigen::Matrix3d& F) const = 0;
  /// Exact tangent dP/dF [Pa], 9 x 9 symmetric, possibly indefinite.
  virtual Matrix9d firstPiolaDerivative(const Eigen::Matrix3d& F) const = 0;
  /// Positive semi-definite approximation of dP/dF [Pa], 9 x 9; equals the exact tangent at F = I.
  virtual Matrix9d projectedFirstPiolaDerivative(const Eigen::Matrix3d& F) const = 0;

  /// Dispatches to firstPiolaDerivative (Exact) or projectedFirstPiolaDerivative (ProjectedSpd).
  Matrix9d tangent(const Eigen::Matrix3d& F, TangentMode mode) const;
  /// firstPiola(F) and tangent(F, mode) together, equal to the separate calls to round-off. The
  /// default makes the two calls; laws whose stress and tangent share work (a decomposition of
  /// F) override it.
  virtual StressAndTangent stressAndTangent(const Eigen::Matrix3d& F, TangentMode mode) const;
  /// For laws whose projectedFirstPiolaDerivative(F) is a rotated isotropic linear tensor
  /// (corotational elasticity): firstPiola(F) and that tangent in the compact form of
  /// RotatedLinearStressAndTangent, so element stiffness needs no 9 x 9 matrix. std::nullopt (the
  /// default) for every other law.
  virtual std::optional<RotatedLinearStressAndTangent> rotatedLinearStressAndTangent(
      const Eigen::Matrix3d& F) const;
};

}  // namespace surgical_sim::core
