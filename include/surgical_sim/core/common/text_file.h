#pragma once

#include <string>

namespace surgical_sim::core {

/// Contents of the text file at `path` (a URDF, a YAML description, ...).
/// @throws std::invalid_argument "cannot read '<path>'" if it cannot be opened or read.
std::string readTextFile(const std::string& path);

}  // namespace surgical_sim::core
