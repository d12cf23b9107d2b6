#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

#include "surgical_sim/ros/cutting_tool_node.h"

namespace surgical_sim::ros_layer {
namespace {

/// Message of the std::invalid_argument CuttingToolNode::validateBlade throws, or "".
std::string bladeProblem(const Eigen::Matrix3Xd& blade) {
  try {
    CuttingToolNode::validateBlade("~blade", blade);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(CuttingTool, ValidateBladeNamesWhatIsWrong) {
  Eigen::Matrix3Xd blade(3, 2);
  blade << 0, 0.02, 0, 0, 0, 0;
  EXPECT_EQ(bladeProblem(blade), "");
  EXPECT_NE(bladeProblem(blade.leftCols(1)).find("~blade has 1 points"), std::string::npos);
  blade(0, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(bladeProblem(blade).find("~blade is not finite"), std::string::npos);
  blade(0, 1) = 2.0;
  EXPECT_NE(bladeProblem(blade).find("farther than 1 m"), std::string::npos);
}

TEST(CuttingTool, ZeroLengthAndOverlongBladesAreRejected) {
  const Eigen::Matrix3Xd coincident = Eigen::Matrix3Xd::Zero(3, 2);
  EXPECT_NE(bladeProblem(coincident).find("total length of 0 m"), std::string::npos);
  Eigen::Matrix3Xd many = Eigen::Matrix3Xd::Zero(3, 100000);
  many.row(0) = Eigen::RowVectorXd::LinSpaced(many.cols(), 0.0, 0.02);
  EXPECT_NE(bladeProblem(many).find("~blade has 100000 points"), std::string::npos);
}

}  // namespace
}  // namespace surgical_sim::ros_layer
