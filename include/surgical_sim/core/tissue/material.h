#pragma once

namespace surgical_sim::core {

/// Isotropic elastic material in SI units. Construct through Material::create, which validates.
struct Material {
  double young_modulus = 0.0;  ///< E [Pa], range (0, 1e12]
  double poisson_ratio = 0.0;  ///< nu [-], range [0, 0.5)
  double density = 0.0;        ///< rho [kg/m^3], range (0, 1e5]

  /// @throws std::invalid_argument naming "material.young_modulus" etc. when out of range.
  static Material create(double young_modulus_pa, double poisson_ratio, double density_kg_m3);
  /// create() applied to the fields of m (a copy, validated).
  static Material validated(const Material& m);

  /// Lame's first parameter lambda = E nu / ((1 + nu)(1 - 2 nu)) [Pa].
  double lambda() const;
  /// Shear modulus mu = E / (2 (1 + nu)) [Pa].
  double mu() const;
};

}  // namespace surgical_sim::core
