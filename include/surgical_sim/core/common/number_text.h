#pragma once

#include <string>

namespace surgical_sim::core {

/// Decimal text of `value` that reads back as the same double: 15 significant digits when they
/// suffice (0.025 stays "0.025"), else 17.
std::string numberText(double value);

}  // namespace surgical_sim::core
