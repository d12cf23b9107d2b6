// tissue_simulator: steps a tissue scene and publishes its surface, contact models and stats.
#include "surgical_sim/ros/run_node.h"
#include "surgical_sim/ros/tissue_simulator_node.h"

namespace {

constexpr const char* kUsage =
    "usage: rosrun surgical_sim tissue_simulator _scene:=<scene.yaml> [_param:=value ...]\n"
    "Steps the tissue of a scene; publishes tissue/surface, tissue/contact_model, tissue/wrench,\n"
    "tissue/stats (docs/nodes.md).\n"
    "private parameters [unit; range; default]:\n"
    "  ~scene [path; required]              runtime scene YAML (docs/scenes.md)\n"
    "  ~realtime [bool; true]               true: wall-clock steps at the scene's time_step;\n"
    "                                       false: lockstep on the tool poses (bag replay)\n"
    "  ~steps_per_pose [-; 1..1000; 1]      lockstep steps per tool pose\n"
    "  ~world_frame [string; world]         frame of wrenches and contact models\n"
    "  ~tissue_frame [string; tissue]       rest frame of the organ\n"
    "  ~surface_rate [Hz; (0, 1000]; 30]    tissue/surface rate in realtime mode\n"
    "  ~max_tool_distance [m; (0, 1000]; 5] farther tool poses are rejected\n";

}  // namespace

int main(int argc, char** argv) {
  return surgical_sim::ros_layer::runNode<surgical_sim::ros_layer::TissueSimulatorNode>(
      argc, argv, "tissue_simulator", kUsage);
}
