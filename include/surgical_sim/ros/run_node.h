#pragma once

#include <ros/ros.h>

#include <exception>

namespace surgical_sim::ros_layer {

/// main() of a node: initializes ROS as `name`, builds Node(nh, private nh) and spins. A
/// constructor error (bad parameter, malformed scene, ...) is logged as fatal, naming the node,
/// and makes the process exit with 1.
template <class Node>
int runNode(int argc, char** argv, const char* name) {
  ros::init(argc, argv, name);
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  try {
    Node node(nh, pnh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("%s: %s", name, e.what());
    return 1;
  }
  return 0;
}

}  // namespace surgical_sim::ros_layer
