// cutting_tool: turns tool/pose + cutting/activate into cutting/blade_sweep.
#include <ros/ros.h>

#include <exception>

#include "surgical_sim/ros/cutting_tool_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "cutting_tool");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  try {
    surgical_sim::ros_layer::CuttingToolNode node(nh, pnh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("cutting_tool: %s", e.what());
    return 1;
  }
  return 0;
}
