#pragma once

#include <string>

namespace surgical_sim::core {

/// Converts the name of a length unit used in mesh files and configs to its size in metres.
/// @param unit one of "m", "cm", "mm", "um" (micrometre).
/// @return metres per unit [m]: 1, 0.01, 0.001 or 1e-6.
/// @throws std::invalid_argument "unknown length unit 'X' (expected m, cm, mm or um)".
double lengthUnitToMetres(const std::string& unit);

}  // namespace surgical_sim::core
