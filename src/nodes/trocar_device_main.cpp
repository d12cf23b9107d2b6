// trocar_device: the 5-DoF active trocar with its 1 kHz haptic loop (joint commands in, motor
// efforts, joint states and the tool-tip pose out).
#include <ros/ros.h>

#include <exception>

#include "surgical_sim/ros/trocar_device_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "trocar_device");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  try {
    surgical_sim::ros_layer::TrocarDeviceNode node(nh, pnh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("trocar_device: %s", e.what());
    return 1;
  }
  return 0;
}
