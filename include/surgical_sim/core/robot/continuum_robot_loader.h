#pragma once

#include <string>

#include "surgical_sim/core/robot/continuum_robot_description.h"

namespace surgical_sim::core {

/// Parses robot `name` from the YAML text of a robot description file (see
/// config/continuum_robot.yaml): top-level map `robots:` of named robots. Lengths are given in
/// metres (keys ending in _m), angles in degrees (_deg), pressures in kPa (_kpa), converted to SI
/// here once. The result is validated (validateContinuumRobotDescription).
/// @param yaml_text contents of the file.
/// @param name key of the robot under `robots`.
/// @param source file name used in error messages.
/// @throws std::invalid_argument "<source>: key 'robots.trunk.vertebra_spacing_m': missing
///         required key" (and likewise for type errors), or the validator's message.
ContinuumRobotDescription parseContinuumRobot(const std::string& yaml_text, const std::string& name,
                                              const std::string& source);

/// Reads `path` and parses robot `name` (parseContinuumRobot).
/// @throws std::invalid_argument if the file cannot be read, or as parseContinuumRobot.
ContinuumRobotDescription loadContinuumRobot(const std::string& path, const std::string& name);

}  // namespace surgical_sim::core
