// tissue_simulator: steps a tissue scene and publishes its surface, contact models and stats.
#include <ros/ros.h>

#include <exception>

#include "surgical_sim/ros/tissue_simulator_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "tissue_simulator");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  try {
    surgical_sim::ros_layer::TissueSimulatorNode node(nh, pnh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("tissue_simulator: %s", e.what());
    return 1;
  }
  return 0;
}
