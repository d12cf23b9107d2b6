// continuum_robot_controller: inverse control of a soft continuum robot (reduced model + QP).
#include "surgical_sim/ros/continuum_robot_node.h"
#include "surgical_sim/ros/run_node.h"

namespace {

constexpr const char* kUsage =
    "usage: rosrun surgical_sim continuum_robot_controller [_param:=value ...]\n"
    "Inverse control of a soft continuum robot: continuum_robot/target in; actuation, shape, tf\n"
    "and joint_states out; services set_target, follow_path, reset (docs/nodes.md).\n"
    "private parameters [unit; range; default]:\n"
    "  ~config [path; <package>/config/continuum_robot.yaml]  robot descriptions\n"
    "  ~robot [trunk|cable; trunk]          description key in ~config\n"
    "  ~rate [Hz; (0, 1000]; 10]            control rate of paths and streamed targets\n"
    "  ~base_frame [string; robot_base]     frame of the model\n"
    "  ~link_prefix [string; vertebra_]     tf frames <prefix>1 .. <prefix>n\n"
    "  ~tip_frame [string; robot_tip]       tf frame of the tip\n"
    "  ~tolerance [m; (0, 1]; 1e-4]         default effector tolerance\n"
    "  ~max_iterations [-; 1..1000; 30]     default iterations of set_target\n"
    "  ~step_iterations [-; 1..1000; 5]     iterations per control step on a path or stream\n";

}  // namespace

int main(int argc, char** argv) {
  return surgical_sim::ros_layer::runNode<surgical_sim::ros_layer::ContinuumRobotNode>(
      argc, argv, "continuum_robot_controller", kUsage);
}
