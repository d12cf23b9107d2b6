#include "surgical_sim/ros/cutting_tool_node.h"

#include <stdexcept>

#include "surgical_sim/BladeSweep.h"
#include "surgical_sim/core/cutting/blade_sweep.h"
#include "surgical_sim/ros/conversions.h"
#include "surgical_sim/ros/parameters.h"

namespace surgical_sim::ros_layer {
namespace {

constexpr char kLog[] = "cutting_tool";

/// Default blade: a 20 mm scalpel edge along the tool x axis from the tip [m].
Eigen::Matrix3Xd defaultBlade() {
  Eigen::Matrix3Xd blade = Eigen::Matrix3Xd::Zero(3, 2);
  blade(0, 1) = 0.02;
  return blade;
}

}  // namespace

CuttingToolNode::CuttingToolNode(ros::NodeHandle& nh, ros::NodeHandle& pnh)
    : blade_T_(pointListParam(pnh, "blade", defaultBlade(), "m")),
      max_tool_distance_(numberParam(pnh, "max_tool_distance", 5.0, {0.0, 1000.0, true}, "m")),
      max_step_(numberParam(pnh, "max_step", 0.1, {0.0, 10.0, true}, "m")) {
  validateBlade("~blade", blade_T_);
  sweep_pub_ = nh.advertise<surgical_sim::BladeSweep>("cutting/blade_sweep", 100);
  pose_sub_ = nh.subscribe("tool/pose", 1000, &CuttingToolNode::onPose, this);
  activate_sub_ = nh.subscribe("cutting/activate", 100, &CuttingToolNode::onActivate, this);
  set_blade_srv_ = nh.advertiseService("cutting/set_blade", &CuttingToolNode::onSetBlade, this);
  ROS_INFO_NAMED(kLog, "blade of %d points, inactive until cutting/activate",
                 static_cast<int>(blade_T_.cols()));
}

void CuttingToolNode::validateBlade(const std::string& name, const Eigen::Matrix3Xd& blade) {
  core::validateBladePolyline(name, blade);
  if (blade.colwise().norm().maxCoeff() > kMaxBladeReach)
    throw std::invalid_argument(name + " has a point farther than 1 m from the tool frame origin");
}

void CuttingToolNode::onPose(const geometry_msgs::PoseStamped::ConstPtr& msg) {
  if (!acceptPose(msg->pose, max_tool_distance_, kLog)) return;
  const Eigen::Isometry3d X_FT = toEigen(msg->pose);
  const Eigen::Matrix3Xd blade_F = X_FT * blade_T_;
  const bool same_frame = msg->header.frame_id == previous_frame_;
  const bool continues = has_previous_ && same_frame && previous_F_.cols() == blade_F.cols() &&
                         (blade_F - previous_F_).colwise().norm().maxCoeff() <= max_step_;
  if (active_ && has_previous_ && !same_frame)
    ROS_WARN_THROTTLE_NAMED(1.0, kLog,
                            "tool/pose in frame '%s' while cutting in frame '%s': no sweep for "
                            "this pose, the sequence restarts in the new frame",
                            msg->header.frame_id.c_str(), previous_frame_.c_str());
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
  try {
    validateBlade("points", blade);
  } catch (const std::invalid_argument& e) {
    res.success = false;
    res.message = e.what();
    return true;
  }
  blade_T_ = blade;
  has_previous_ = false;
  res.success = true;
  res.message = "blade of " + std::to_string(blade.cols()) + " points";
  return true;
}

}  // namespace surgical_sim::ros_layer
