#include "surgical_sim/core/haptics/trocar_geometry.h"

#include <limits>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

TrocarGeometry::TrocarGeometry()
    : tip_offset(std::numeric_limits<double>::quiet_NaN()),
      shaft_length(std::numeric_limits<double>::quiet_NaN()),
      shaft_diameter(std::numeric_limits<double>::quiet_NaN()),
      cradle_diameter(std::numeric_limits<double>::quiet_NaN()),
      jaw_length(std::numeric_limits<double>::quiet_NaN()) {}

TrocarGeometry TrocarGeometry::chendebPrototype() {
  TrocarGeometry g;
  g.tip_offset = 0.020;
  g.shaft_length = 0.400;
  g.shaft_diameter = 0.005;
  g.cradle_diameter = 0.100;
  g.jaw_length = 0.015;
  return g;
}

void validateTrocarGeometry(const TrocarGeometry& geometry) {
  requirePositive("trocar.shaft_length", geometry.shaft_length, "m");
  requireInRange("trocar.tip_offset", geometry.tip_offset, 0.0, geometry.shaft_length, "m");
  requirePositive("trocar.shaft_diameter", geometry.shaft_diameter, "m");
  requirePositive("trocar.cradle_diameter", geometry.cradle_diameter, "m");
  requirePositive("trocar.jaw_length", geometry.jaw_length, "m");
}

}  // namespace surgical_sim::core
