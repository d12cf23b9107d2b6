#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "surgical_sim/core/robot/continuum_robot_description.h"

namespace surgical_sim::core {

/// Axial stations of the soft part of gap `gap` [m], frame robot_base: from
/// x_gap + vertebra_thickness/2 to x_{gap+1} - vertebra_thickness/2 in mesh.axial_layers layers.
std::vector<double> sectionStations(const ContinuumRobotDescription& description, int gap);

/// Cache key of gap `gap`: every quantity the compliance depends on (length, radii, thickness,
/// material, resolution), printed with 17 significant digits.
std::string sectionCacheKey(const ContinuumRobotDescription& description, int gap);

/// Result of computeSectionCompliances.
struct SectionCompliances {
  std::vector<Eigen::Matrix<double, 6, 6>> compliance;  ///< C of gap k, frame of rigid node k
  int cache_hits = 0;                                   ///< gaps read from the cache
  double seconds = 0.0;                                 ///< wall time of the whole call [s]
};

/// Condensed compliance of every gap (condenseSection on makeTubeMesh of the gap), read from or
/// written to the cache in cache_directory ("" disables caching). Identical gaps are computed
/// once. Prints a progress bar on stderr once the call has run for more than 1 s.
/// @throws std::invalid_argument if the description is invalid.
SectionCompliances computeSectionCompliances(const ContinuumRobotDescription& description,
                                             const std::string& cache_directory);

}  // namespace surgical_sim::core
