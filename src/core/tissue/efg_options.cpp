#include "surgical_sim/core/tissue/efg_options.h"

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

void EfgOptions::validate() const {
  requirePositive("efg.spacing", spacing, "m");
  requireInRange("efg.neighbours", neighbours, kMinNeighbours, kMaxNeighbours, "");
  requireInRange("efg.kernel_support", kernel_support, 1.1, 10.0, "");
  requireInRange("efg.volume_samples", volume_samples, 1, kMaxVolumeSamples, "");
  requireInRange("efg.stabilization", stabilization, 0.0, 1.0, "");
}

}  // namespace surgical_sim::core
