#include "surgical_sim/core/cutting/blade_sweep.h"

#include <stdexcept>
#include <string>

namespace surgical_sim::core {

void validateBladeSweep(const BladeSweep& sweep) {
  if (sweep.start.cols() < 2)
    throw std::invalid_argument("blade_sweep.start has " + std::to_string(sweep.start.cols()) +
                                " points; a blade polyline needs at least 2");
  if (sweep.end.cols() != sweep.start.cols())
    throw std::invalid_argument("blade_sweep.end has " + std::to_string(sweep.end.cols()) +
                                " points but blade_sweep.start has " +
                                std::to_string(sweep.start.cols()));
  if (!sweep.start.allFinite()) throw std::invalid_argument("blade_sweep.start is not finite");
  if (!sweep.end.allFinite()) throw std::invalid_argument("blade_sweep.end is not finite");
}

}  // namespace surgical_sim::core
