#pragma once

#include <string>

namespace surgical_sim::core {

/// Configuration-time validators. Each throws std::invalid_argument whose message names the
/// parameter, its unit and the accepted range, e.g.
/// "material.young_modulus = -5 Pa is out of range: must be finite and > 0".

/// value must be finite and > 0.
void requirePositive(const std::string& name, double value, const std::string& unit);
/// value must be finite and >= 0.
void requireNonNegative(const std::string& name, double value, const std::string& unit);
/// value must be finite and lo <= value <= hi (closed interval).
void requireInRange(const std::string& name, double value, double lo, double hi,
                    const std::string& unit);
/// value must be finite and lo <= value < hi (half-open interval).
void requireInHalfOpenRange(const std::string& name, double value, double lo, double hi,
                            const std::string& unit);
/// value must be finite.
void requireFinite(const std::string& name, double value, const std::string& unit);

}  // namespace surgical_sim::core
