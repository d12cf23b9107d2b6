#pragma once

#include <ros/ros.h>

#include <cstring>
#include <exception>
#include <iostream>

namespace surgical_sim::ros_layer {

/// main() of a node. With `--help` or `-h` among the arguments it prints `usage` (the node's
/// command line and private parameters) on stdout and returns 0 before touching ROS. Otherwise it
/// initializes ROS as `name`, builds Node(nh, private nh) and spins. A constructor error (bad
/// parameter, malformed scene, ...) is logged as fatal, naming the node, and makes the process
/// exit with 1.
template <class Node>
int runNode(int argc, char** argv, const char* name, const char* usage) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::cout << usage;
      return 0;
    }
  }
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
