// trocar_device: the 5-DoF active trocar with its 1 kHz haptic loop (joint commands in, motor
// efforts, joint states and the tool-tip pose out).
#include "surgical_sim/ros/run_node.h"
#include "surgical_sim/ros/trocar_device_node.h"

namespace {

constexpr const char* kUsage =
    "usage: rosrun surgical_sim trocar_device [_param:=value ...]\n"
    "The 5-DoF active trocar: trocar/joint_command and tissue/contact_model in; joint_states,\n"
    "tool/pose, trocar/motor_effort, trocar/rendered_wrench, trocar/loop_stats out "
    "(docs/nodes.md).\n"
    "private parameters [unit; range; default]:\n"
    "  ~rate [Hz; 100..20000; 1000]             haptic loop rate\n"
    "  ~publish_rate [Hz; (0, 1000]; 100]       joint_states, motor_effort, rendered_wrench\n"
    "  ~stats_rate [Hz; (0, 100]; 1]            trocar/loop_stats\n"
    "  ~pose_rate [Hz; [0, 1000]; 0]            periodic tool/pose besides one per command\n"
    "  ~stale_age [s; (0, 10]; 0.1]             older contact models are stale\n"
    "  ~stale_policy [fade|hold; fade]          what a stale model renders\n"
    "  ~fade_time [s; [0, 10]; 0.05]            fade duration of a stale force\n"
    "  ~pitch_limit_deg ~yaw_limit_deg [deg; [0, 70]; 45]\n"
    "  ~coupling_stiffness [N/m; (0, 1e6]; 3000]\n"
    "  ~coupling_damping [N s/m; [0, 1e4]; 2]\n"
    "  ~passivity [bool; true]                  passivity observer / controller\n"
    "  ~x ~y ~z [m; [-10, 10]; 0 0 0.2]         fulcrum position in ~world_frame\n"
    "  ~roll ~pitch ~yaw [rad; [-2pi, 2pi]; pi 0 0]  trocar frame orientation (fixed-axis rpy)\n"
    "  ~realtime_priority [-; 0..99; 0]         SCHED_FIFO priority of the loop (0: none)\n"
    "  ~world_frame [world] ~trocar_frame [trocar] ~joint_prefix [trocar_]\n"
    "  ~publish_trocar_tf [bool; true]          static tf ~world_frame -> ~trocar_frame\n";

}  // namespace

int main(int argc, char** argv) {
  return surgical_sim::ros_layer::runNode<surgical_sim::ros_layer::TrocarDeviceNode>(
      argc, argv, "trocar_device", kUsage);
}
