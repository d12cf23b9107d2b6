#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "surgical_sim/core/robot/continuum_robot_description.h"

namespace surgical_sim::core {

/// An active trocar of a scene: its name T ([A-Za-z][A-Za-z0-9_]*; also its tf frame and joint
/// prefix "T_") and the pose of its frame F (fulcrum, z along the cannula) in world.
struct TrocarPlacement {
  std::string name;
  Eigen::Isometry3d X_WF = Eigen::Isometry3d::Identity();
};

/// The continuum robot of a scene: its description name (a robot of config/continuum_robot.yaml)
/// and the pose of robot_base in world.
struct RobotPlacement {
  std::string description;
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
};

/// URDF of a scene's instruments (robot_description of scene.launch): link `world`; per trocar T
/// a fixed joint `world_to_T` from `world` to `T` at X_WF, then the links, joints and materials
/// of `trocar_urdf` (the text of urdf/active_trocar.urdf) with every name prefixed (`trocar` ->
/// `T`, `trocar_x` -> `T_x`, any other `x` -> `T_x`); with a robot, a fixed joint
/// `world_to_robot_base` from `world` to `robot_base` at X_WB, then continuumRobotUrdf of the
/// description named robot->description among `robots`. Materials are shared by name.
/// @throws std::invalid_argument naming the problem: an invalid or repeated trocar name, a
/// non-rigid pose, trocar_urdf that is not a <robot> document, an unknown robot description
/// (the known names are listed), or a result urdfdom rejects (e.g. clashing names).
std::string sceneUrdf(const std::vector<TrocarPlacement>& trocars,
                      const std::optional<RobotPlacement>& robot, const std::string& trocar_urdf,
                      const std::vector<ContinuumRobotDescription>& robots);

}  // namespace surgical_sim::core
