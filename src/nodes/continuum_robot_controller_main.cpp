// continuum_robot_controller: inverse control of a soft continuum robot (reduced model + QP).
#include "surgical_sim/ros/continuum_robot_node.h"
#include "surgical_sim/ros/run_node.h"

int main(int argc, char** argv) {
  return surgical_sim::ros_layer::runNode<surgical_sim::ros_layer::ContinuumRobotNode>(
      argc, argv, "continuum_robot_controller");
}
