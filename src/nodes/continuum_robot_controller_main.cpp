// continuum_robot_controller: inverse control of a soft continuum robot (reduced model + QP).
#include <ros/ros.h>

#include <exception>

#include "surgical_sim/ros/continuum_robot_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "continuum_robot_controller");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  try {
    surgical_sim::ros_layer::ContinuumRobotNode node(nh, pnh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("continuum_robot_controller: %s", e.what());
    return 1;
  }
  return 0;
}
