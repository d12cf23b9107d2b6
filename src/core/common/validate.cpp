#include "surgical_sim/core/common/validate.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace surgical_sim::core {
namespace {

[[noreturn]] void fail(const std::string& name, double value, const std::string& unit,
                       const std::string& rule) {
  std::ostringstream msg;
  msg << name << " = " << value << (unit.empty() ? "" : " ") << unit << " is out of range: must be "
      << rule;
  throw std::invalid_argument(msg.str());
}

std::string withUnit(double v, const std::string& unit) {
  std::ostringstream s;
  s << v << (unit.empty() ? "" : " ") << unit;
  return s.str();
}

}  // namespace

void requireFinite(const std::string& name, double value, const std::string& unit) {
  if (!std::isfinite(value)) fail(name, value, unit, "finite");
}

void requirePositive(const std::string& name, double value, const std::string& unit) {
  if (!std::isfinite(value) || value <= 0.0) fail(name, value, unit, "finite and > 0");
}

void requireNonNegative(const std::string& name, double value, const std::string& unit) {
  if (!std::isfinite(value) || value < 0.0) fail(name, value, unit, "finite and >= 0");
}

void requireInRange(const std::string& name, double value, double lo, double hi,
                    const std::string& unit) {
  if (!std::isfinite(value) || value < lo || value > hi)
    fail(name, value, unit, "in [" + withUnit(lo, unit) + ", " + withUnit(hi, unit) + "]");
}

void requireInHalfOpenRange(const std::string& name, double value, double lo, double hi,
                            const std::string& unit) {
  if (!std::isfinite(value) || value < lo || value >= hi)
    fail(name, value, unit, "in [" + withUnit(lo, unit) + ", " + withUnit(hi, unit) + ")");
}

}  // namespace surgical_sim::core
