#include "surgical_sim/core/solve/integrator_settings.h"

#include <limits>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

void validateIntegratorSettings(const IntegratorSettings& settings) {
  requireInRange("integrator.max_iterations", settings.max_iterations, 1,
                 std::numeric_limits<int>::max(), "");
  requireInHalfOpenRange("integrator.relative_tolerance", settings.relative_tolerance,
                         std::numeric_limits<double>::min(), 1.0, "");
  requireInRange("integrator.max_line_search_halvings", settings.max_line_search_halvings, 0, 60,
                 "");
  requirePositive("integrator.blow_up_energy_ratio", settings.blow_up_energy_ratio, "");
  requireInRange("integrator.max_load_step_levels", settings.max_load_step_levels, 0, 16, "");
}

}  // namespace surgical_sim::core
