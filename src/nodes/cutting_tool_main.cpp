// cutting_tool: turns tool/pose + cutting/activate into cutting/blade_sweep.
#include "surgical_sim/ros/cutting_tool_node.h"
#include "surgical_sim/ros/run_node.h"

int main(int argc, char** argv) {
  return surgical_sim::ros_layer::runNode<surgical_sim::ros_layer::CuttingToolNode>(argc, argv,
                                                                                    "cutting_tool");
}
