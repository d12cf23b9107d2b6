#include "surgical_sim/core/tissue/material.h"

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

Material Material::create(double young_modulus_pa, double poisson_ratio, double density_kg_m3) {
  requireInRange("material.young_modulus", young_modulus_pa, 1e-12, 1e12, "Pa");
  requireInHalfOpenRange("material.poisson_ratio", poisson_ratio, 0.0, 0.5, "");
  requireInRange("material.density", density_kg_m3, 1e-12, 1e5, "kg/m^3");
  Material m;
  m.young_modulus = young_modulus_pa;
  m.poisson_ratio = poisson_ratio;
  m.density = density_kg_m3;
  return m;
}

Material Material::validated(const Material& m) {
  return create(m.young_modulus, m.poisson_ratio, m.density);
}

double Material::lambda() const {
  return young_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
}

double Material::mu() const { return young_modulus / (2.0 * (1.0 + poisson_ratio)); }

}  // namespace surgical_sim::core
