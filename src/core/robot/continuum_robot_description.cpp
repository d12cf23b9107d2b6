#include "surgical_sim/core/robot/continuum_robot_description.h"

#include <algorithm>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

double ContinuumRobotDescription::outerRadiusAt(double x) const {
  const double t = length() > 0.0 ? x / length() : 0.0;
  return outer_radius_base + (outer_radius_tip - outer_radius_base) * t;
}

void validateContinuumRobotDescription(const ContinuumRobotDescription& d) {
  const std::string p = "robot." + (d.name.empty() ? std::string("<unnamed>") : d.name) + ".";
  if (d.name.empty()) throw std::invalid_argument("robot.name must not be empty");
  requireInRange(p + "num_vertebrae", d.num_vertebrae, 1, 200, "");
  requirePositive(p + "vertebra_spacing", d.vertebra_spacing, "m");
  requireInHalfOpenRange(p + "vertebra_thickness", d.vertebra_thickness, 0.0, d.vertebra_spacing,
                         "m");
  requirePositive(p + "inner_radius", d.inner_radius, "m");
  requireInRange(p + "outer_radius_base", d.outer_radius_base, d.inner_radius * (1.0 + 1e-9), 10.0,
                 "m");
  requireInRange(p + "outer_radius_tip", d.outer_radius_tip, d.inner_radius * (1.0 + 1e-9), 10.0,
                 "m");
  Material::validated(d.material);
  requireNonNegative(p + "vertebra_mass", d.vertebra_mass, "kg");
  requireInRange(p + "mesh.radial_layers", d.mesh.radial_layers, 1, 16, "");
  requireInRange(p + "mesh.circumferential_segments", d.mesh.circumferential_segments, 6, 128, "");
  requireInRange(p + "mesh.axial_layers", d.mesh.axial_layers, 1, 32, "");
  if (d.numActuators() == 0)
    throw std::invalid_argument(p + "chambers / cables: at least one actuator is required");
  const double r_min = std::min(d.outer_radius_base, d.outer_radius_tip);
  for (size_t i = 0; i < d.chambers.size(); ++i) {
    const auto& c = d.chambers[i];
    const std::string q = p + "chambers[" + std::to_string(i) + "].";
    requireInRange(q + "first_gap", c.first_gap, 0, d.num_vertebrae - 1, "");
    requireInRange(q + "last_gap", c.last_gap, c.first_gap, d.num_vertebrae - 1, "");
    requireFinite(q + "angle", c.angle, "rad");
    requireInRange(q + "radial_offset", c.radial_offset, 1e-9, r_min, "m");
    requireInRange(q + "radius", c.radius, 1e-9, c.radial_offset * (1.0 - 1e-9), "m");
    requireFinite(q + "pressure_min", c.pressure_min, "Pa");
    requireInRange(q + "pressure_max", c.pressure_max, c.pressure_min + 1e-9, 1e8, "Pa");
  }
  for (size_t i = 0; i < d.cables.size(); ++i) {
    const auto& c = d.cables[i];
    const std::string q = p + "cables[" + std::to_string(i) + "].";
    requireInRange(q + "last_vertebra", c.last_vertebra, 1, d.num_vertebrae, "");
    requireFinite(q + "angle", c.angle, "rad");
    requireInRange(q + "radial_offset", c.radial_offset, 1e-9, 10.0, "m");
    requirePositive(q + "tension_max", c.tension_max, "N");
  }
}

}  // namespace surgical_sim::core
