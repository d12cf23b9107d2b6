#include <gtest/gtest.h>

#include <limits>

#include "surgical_sim/ros/cutting_tool_node.h"

namespace surgical_sim::ros_layer {
namespace {

TEST(CuttingTool, BladeProblemNamesWhatIsWrong) {
  Eigen::Matrix3Xd blade(3, 2);
  blade << 0, 0.02, 0, 0, 0, 0;
  EXPECT_EQ(CuttingToolNode::bladeProblem(blade), "");
  EXPECT_NE(CuttingToolNode::bladeProblem(blade.leftCols(1)).find("at least 2 points"),
            std::string::npos);
  blade(0, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(CuttingToolNode::bladeProblem(blade).find("not finite"), std::string::npos);
  blade(0, 1) = 2.0;
  EXPECT_NE(CuttingToolNode::bladeProblem(blade).find("farther than 1 m"), std::string::npos);
}

}  // namespace
}  // namespace surgical_sim::ros_layer
