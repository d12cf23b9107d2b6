#include "surgical_sim/core/mesh/length_unit.h"

#include <stdexcept>

namespace surgical_sim::core {

double lengthUnitToMetres(const std::string& unit) {
  if (unit == "m") return 1.0;
  if (unit == "cm") return 0.01;
  if (unit == "mm") return 0.001;
  if (unit == "um") return 1e-6;
  throw std::invalid_argument("unknown length unit '" + unit + "' (expected m, cm, mm or um)");
}

}  // namespace surgical_sim::core
