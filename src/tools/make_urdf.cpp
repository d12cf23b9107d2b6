// make_urdf: prints the URDF of a scene's instruments (ROS-free; roslaunch loads its output as
// robot_description, e.g. <param name="robot_description" command="rosrun surgical_sim make_urdf
// --robot trunk"/>). See usage() below.
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "package_dirs.h"
#include "surgical_sim/core/common/text_file.h"
#include "surgical_sim/core/robot/continuum_robot_loader.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/scene_urdf.h"

namespace {

using namespace surgical_sim::core;

constexpr char kUsage[] =
    "usage: make_urdf [--robot NAME [--config PATH] [--robot-base X,Y,Z,R,P,Y]]\n"
    "                 [--trocars \"T:X,Y,Z,R,P,Y;...\" [--trocar-urdf PATH]]\n"
    "       make_urdf --scene SCENE.yaml [--plan] [--config PATH] [--trocar-urdf PATH]\n"
    "       make_urdf --help\n"
    "Prints on stdout the URDF of a scene's instruments: link world; each trocar T (a prefixed\n"
    "copy of the trocar URDF, names T, T_pitch, ..., T_tool_tip) fixed to world by joint\n"
    "world_to_T at its fulcrum pose; the continuum robot NAME of the description file (its base\n"
    "robot_base fixed to world by joint world_to_robot_base, links vertebra_1..n, robot_tip).\n"
    "Poses: position X,Y,Z [m] and fixed-axis roll, pitch, yaw R,P,Y [rad] in world.\n"
    "  --robot NAME          robot description (trunk | cable in the shipped file)\n"
    "  --config PATH         description file (default: config/continuum_robot.yaml)\n"
    "  --robot-base POSE     robot_base in world (default: 0,0,0,0,0,0)\n"
    "  --trocars SPEC        ';'-separated T:POSE, e.g. \"trocar_0:-0.05,0,0.2,3.14159,0,0\"\n"
    "  --trocar-urdf PATH    trocar URDF (default: urdf/active_trocar.urdf)\n"
    "  --scene SCENE.yaml    the trocars and robot of a runtime scene (validated; exit 1 naming\n"
    "                        the key of an invalid scene)\n"
    "  --plan                with --scene: print the nodes the scene needs instead, one per line:\n"
    "                        'tissue', 'trocar T', 'cutting POSE_TOPIC EDGE_YAML', 'robot NAME'\n";

/// The nodes a runtime scene needs (scene.launch reads these lines).
std::string launchPlan(const RuntimeScene& scene) {
  std::ostringstream out;
  out.precision(17);
  out << "tissue\n";
  for (const TrocarSpec& t : scene.trocars) out << "trocar " << t.name << "\n";
  for (const BladeSpec& b : scene.blades) {
    out << "cutting " << scene.tools[static_cast<std::size_t>(b.tool)].pose_topic << " [";
    for (Eigen::Index k = 0; k < b.edge.cols(); ++k)
      out << (k ? ", " : "") << "[" << b.edge(0, k) << ", " << b.edge(1, k) << ", " << b.edge(2, k)
          << "]";
    out << "]\n";
  }
  if (scene.robot) out << "robot " << scene.robot->description << "\n";
  return out.str();
}

/// Pose from "x,y,z,roll,pitch,yaw" ([m], [rad], fixed-axis rpy).
Eigen::Isometry3d parsePose(const std::string& text, const std::string& what) {
  std::istringstream in(text);
  double v[6];
  char comma = ',';
  for (int i = 0; i < 6; ++i) {
    if ((i > 0 && !(in >> comma)) || comma != ',' || !(in >> v[i]) || !std::isfinite(v[i]))
      throw std::invalid_argument(what + " '" + text +
                                  "' is invalid: must be six finite numbers X,Y,Z,R,P,Y");
  }
  if (in >> comma)
    throw std::invalid_argument(what + " '" + text + "' is invalid: more than six numbers");
  return Eigen::Translation3d(v[0], v[1], v[2]) *
         Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(v[4], Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitX());
}

std::vector<TrocarPlacement> parseTrocars(const std::string& spec) {
  std::vector<TrocarPlacement> trocars;
  std::istringstream in(spec);
  for (std::string item; std::getline(in, item, ';');) {
    const std::size_t colon = item.find(':');
    if (colon == std::string::npos)
      throw std::invalid_argument("--trocars item '" + item +
                                  "' is invalid: must be T:X,Y,Z,R,P,Y");
    trocars.push_back(
        {item.substr(0, colon),
         parsePose(item.substr(colon + 1), "--trocars pose of " + item.substr(0, colon))});
  }
  if (trocars.empty()) throw std::invalid_argument("--trocars is empty");
  return trocars;
}

}  // namespace

int main(int argc, char** argv) {
  std::string robot_name, config = surgical_sim::tools::configDir() + "/continuum_robot.yaml";
  std::string trocar_spec,
      trocar_urdf = surgical_sim::tools::packageDir() + "/urdf/active_trocar.urdf";
  std::string robot_base = "0,0,0,0,0,0";
  std::string scene_path;
  bool plan = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      return 0;
    }
    if (arg == "--plan") {
      plan = true;
      continue;
    }
    std::string* value = arg == "--robot"         ? &robot_name
                         : arg == "--config"      ? &config
                         : arg == "--robot-base"  ? &robot_base
                         : arg == "--trocars"     ? &trocar_spec
                         : arg == "--trocar-urdf" ? &trocar_urdf
                         : arg == "--scene"       ? &scene_path
                                                  : nullptr;
    if (!value || i + 1 == argc) {
      std::cerr << "make_urdf: " << (value ? "missing value after " : "unknown argument ") << arg
                << "\n"
                << kUsage;
      return 2;
    }
    *value = argv[++i];
  }
  if (robot_name.empty() && trocar_spec.empty() && scene_path.empty()) {
    std::cerr << "make_urdf: nothing to describe: give --scene, --robot and/or --trocars\n"
              << kUsage;
    return 2;
  }
  if (!scene_path.empty() && (!robot_name.empty() || !trocar_spec.empty())) {
    std::cerr << "make_urdf: --scene takes its trocars and robot from the scene: no --robot or "
                 "--trocars with it\n";
    return 2;
  }
  if (plan && scene_path.empty()) {
    std::cerr << "make_urdf: --plan needs --scene\n";
    return 2;
  }
  try {
    std::optional<RobotPlacement> robot;
    std::vector<TrocarPlacement> trocars;
    if (!scene_path.empty()) {
      const RuntimeScene scene = loadRuntimeScene(scene_path);
      if (plan) {
        std::cout << launchPlan(scene);
        return 0;
      }
      for (const TrocarSpec& t : scene.trocars) trocars.push_back({t.name, t.X_WF});
      if (scene.robot) {
        robot_name = scene.robot->description;
        robot = RobotPlacement{robot_name, scene.robot->X_WB};
      }
    }
    std::vector<ContinuumRobotDescription> descriptions;
    if (!robot_name.empty()) {
      descriptions.push_back(loadContinuumRobot(config, robot_name));
      if (!robot) robot = RobotPlacement{robot_name, parsePose(robot_base, "--robot-base")};
    }
    if (!trocar_spec.empty()) trocars = parseTrocars(trocar_spec);
    const std::string trocar_text = trocars.empty() ? std::string() : readTextFile(trocar_urdf);
    std::cout << sceneUrdf(trocars, robot, trocar_text, descriptions);
  } catch (const std::invalid_argument& e) {
    std::cerr << "make_urdf: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
