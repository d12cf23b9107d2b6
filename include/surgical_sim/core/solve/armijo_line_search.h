#pragma once

#include <cmath>
#include <limits>

namespace surgical_sim::core {

/// Outcome of armijoLineSearch.
struct LineSearchResult {
  bool accepted = false;  ///< a step satisfying the Armijo condition (or a round-off step) found
  double step = 0.0;      ///< accepted step length [-]
  double value = 0.0;     ///< merit value at the accepted step
};

/// Backtracking line search with the Armijo condition phi(s) <= phi(0) + c s slope, c = 1e-4,
/// s = 1, 1/2, 1/4, ... (max_halvings halvings). Allocation-free (merit is a callable, inlined).
///
/// @param value0 merit value phi(0)
/// @param slope directional derivative phi'(0) = grad . dx; must be < 0 (else not accepted)
/// @param scale magnitude of the merit's terms; when -slope is below its round-off
///        (1e-11 scale) the decrease is unmeasurable and the full step is taken untested
/// @param max_halvings number of halvings, >= 0
/// @param merit callable double(double s) evaluating phi(s) (typically at x + s dx); the last
///        call made is always at the returned step, so a trial buffer it fills is the result
template <class Merit>
LineSearchResult armijoLineSearch(double value0, double slope, double scale, int max_halvings,
                                  Merit&& merit) {
  constexpr double kArmijo = 1e-4;
  constexpr double kRoundOff = 1e-11;
  LineSearchResult result;
  if (!(slope < 0.0) || !std::isfinite(slope)) return result;
  if (-slope <= kRoundOff * scale) {
    result.value = merit(1.0);
    result.accepted = std::isfinite(result.value);
    result.step = 1.0;
    return result;
  }
  double step = 1.0;
  for (int k = 0; k <= max_halvings; ++k) {
    const double value = merit(step);
    if (std::isfinite(value) && value <= value0 + kArmijo * step * slope) {
      result.accepted = true;
      result.step = step;
      result.value = value;
      return result;
    }
    step *= 0.5;
  }
  return result;
}

}  // namespace surgical_sim::core
