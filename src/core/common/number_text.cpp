#include "surgical_sim/core/common/number_text.h"

#include <cstdio>
#include <cstdlib>

namespace surgical_sim::core {

std::string numberText(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.15g", value);
  if (std::strtod(text, nullptr) != value) std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

}  // namespace surgical_sim::core
