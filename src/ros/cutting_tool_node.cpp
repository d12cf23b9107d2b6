#include "surgical_sim/ros/cutting_tool_node.h"

#include <stdexcept>
#include <vector>

#include "surgical_sim/BladeSweep.h"
#include "surgical_sim/ros/conversions.h"

namespace surgical_sim::ros_layer {

CuttingToolNode::CuttingToolNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
  std::vector<double> blade{0.0, 0.0, 0.0, 0.02, 0.0, 0.0};
  pnh.param("blade", blade, blade);
  pnh.param("max_tool_distance", max_tool_distance_, max_tool_distance_);
  pnh.param("max_step", max_step_, max_step_);
  if (blade.size() % 3 != 0)
    throw std::invalid_argument("~blade has " + std::to_string(blade.size()) +
                                " numbers; expected x y z per point");
  blade_T_ = Eigen::Map<const Eigen::Matrix3Xd>(blade.data(), 3,
                                                static_cast<Eigen::Index>(blade.size() / 3));
  const std::string problem = bladeProblem(blade_T_);
  if (!problem.empty()) throw std::invalid_argument("~blade: " + problem);
  if (!(max_tool_distance_ > 0.0)) throw std::invalid_argument("~max_tool_distance must be > 0 m");
  if (!(max_step_ > 0.0)) throw std::invalid_argument("~max_step must be > 0 m");

  sweep_pub_ = nh.advertise<surgical_sim::BladeSweep>("cutting/blade_sweep", 100);
  pose_sub_ = nh.subscribe("tool/pose", 1000, &CuttingToolNode::onPose, this);
  activate_sub_ = nh.subscribe("cutting/activate", 100, &CuttingToolNode::onActivate, this);
  set_blade_srv_ = nh.advertiseService("cutting/set_blade", &CuttingToolNode::onSetBlade, this);
  ROS_INFO_NAMED("cutting_tool", "blade of %d points, inactive until cutting/activate",
                 static_cast<int>(blade_T_.cols()));
}

std::string CuttingToolNode::bladeProblem(const Eigen::Matrix3Xd& blade) {
  if (blade.cols() < 2)
    return "a blade polyline needs at least 2 points, got " + std::to_string(blade.cols());
  if (!blade.allFinite()) return "a blade point is not finite";
  if (blade.colwise().norm().maxCoeff() > 1.0)
    return "a blade point is farther than 1 m from the tool frame origin";
  return "";
}

void CuttingToolNode::onPose(const geometry_msgs::PoseStamped::ConstPtr& msg) {
  if (!isUsablePose(msg->pose, max_tool_distance_)) {
    ROS_WARN_THROTTLE_NAMED(1.0, "cutting_tool",
                            "rejected tool pose: NaN/Inf, zero quaternion or farther than %.3g m "
                            "(~max_tool_distance) from the origin",
                            max_tool_distance_);
    return;
  }
  const Eigen::Isometry3d X_FT = toEigen(msg->pose);
  const Eigen::Matrix3Xd blade_F = X_FT * blade_T_;
  const bool continues = has_previous_ && msg->header.frame_id == previous_frame_ &&
                         previous_F_.cols() == blade_F.cols() &&
                         (blade_F - previous_F_).colwise().norm().maxCoeff() <= max_step_;
  if (active_ && continues) {
    surgical_sim::BladeSweep sweep;
    sweep.header = msg->header;
    sweep.stamp_start = previous_stamp_;
    sweep.stamp_end = msg->header.stamp;
    for (Eigen::Index i = 0; i < blade_F.cols(); ++i) {
      sweep.start.push_back(toPointMsg(previous_F_.col(i)));
      sweep.end.push_back(toPointMsg(blade_F.col(i)));
    }
    sweep_pub_.publish(sweep);
  }
  previous_F_ = blade_F;
  previous_frame_ = msg->header.frame_id;
  previous_stamp_ = msg->header.stamp;
  has_previous_ = true;
}

void CuttingToolNode::onActivate(const std_msgs::Bool::ConstPtr& msg) {
  if (msg->data && !active_) has_previous_ = false;  // a new sequence from the next pose
  active_ = msg->data;
}

bool CuttingToolNode::onSetBlade(surgical_sim::SetBlade::Request& req,
                                 surgical_sim::SetBlade::Response& res) {
  Eigen::Matrix3Xd blade(3, static_cast<Eigen::Index>(req.points.size()));
  for (std::size_t i = 0; i < req.points.size(); ++i)
    blade.col(static_cast<Eigen::Index>(i)) = toEigen(req.points[i]);
  res.message = bladeProblem(blade);
  res.success = res.message.empty();
  if (!res.success) return true;
  blade_T_ = blade;
  has_previous_ = false;
  res.message = "blade of " + std::to_string(blade.cols()) + " points";
  return true;
}

}  // namespace surgical_sim::ros_layer
