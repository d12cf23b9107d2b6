// cutting_tool: turns tool/pose + cutting/activate into cutting/blade_sweep.
#include "surgical_sim/ros/cutting_tool_node.h"
#include "surgical_sim/ros/run_node.h"

namespace {

constexpr const char* kUsage =
    "usage: rosrun surgical_sim cutting_tool [_param:=value ...]\n"
    "Blade model: tool/pose and cutting/activate in, cutting/blade_sweep out; service\n"
    "cutting/set_blade (docs/nodes.md).\n"
    "private parameters [unit; range; default]:\n"
    "  ~blade [m; 2..1000 points; [[0,0,0],[0.02,0,0]]]  blade polyline in the tool frame,\n"
    "                                       [[x,y,z], ...] or flat x0 y0 z0 x1 y1 z1 ...\n"
    "  ~max_tool_distance [m; (0, 1000]; 5] farther tool poses are rejected\n"
    "  ~max_step [m; (0, 10]; 0.1]          a longer blade jump restarts the sweep sequence\n";

}  // namespace

int main(int argc, char** argv) {
  return surgical_sim::ros_layer::runNode<surgical_sim::ros_layer::CuttingToolNode>(
      argc, argv, "cutting_tool", kUsage);
}
