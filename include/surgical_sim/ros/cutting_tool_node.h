#pragma once

#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>

#include <Eigen/Geometry>
#include <string>

#include "surgical_sim/SetBlade.h"

namespace surgical_sim::ros_layer {

/// Node `cutting_tool`: turns tool motion and activation into blade sweeps. No physics.
///
/// Subscribes `tool/pose` (PoseStamped: pose X_FT of the tool frame T in frame F) and
/// `cutting/activate` (std_msgs/Bool: the pedal). While active, every pose after the first one
/// publishes `cutting/blade_sweep` (BladeSweep in frame F) holding the blade polyline at the
/// previous and at the current pose with both stamps. Activating starts a new sweep sequence
/// (the first pose after activation is only remembered); a pose in a different frame than the
/// previous one also restarts it (with a throttled warning while active), and so does a jump.
/// Service `cutting/set_blade` (SetBlade) replaces the blade polyline (checked by validateBlade).
/// Parameters (private; all strict, see parameters.h):
///   ~blade [m; list; [0, 0, 0, 0.02, 0, 0]]  blade polyline in the tool frame: x0 y0 z0 x1 y1
///                                z1 ... or [[x0, y0, z0], [x1, y1, z1], ...], also given as a
///                                YAML string (rosrun _blade:="[[0,0,0],[0,0,0.02]]"); checked
///                                by validateBlade (default: a 20 mm scalpel edge along the tool
///                                x axis from the tip)
///   ~max_tool_distance [m; (0, 1000]; 5]  poses farther than this from the origin are rejected
///   ~max_step [m; (0, 10]; 0.1]  a pose that moves the blade farther than this since the previous
///                                pose restarts the sequence instead of cutting (a jump, not a cut)
/// Bad parameters throw std::invalid_argument from the constructor naming the parameter.
class CuttingToolNode {
 public:
  CuttingToolNode(ros::NodeHandle& nh, ros::NodeHandle& pnh);

  /// Farthest accepted blade point from the tool frame origin [m].
  static constexpr double kMaxBladeReach = 1.0;

  /// Checks a blade polyline [m] (tool frame): core::validateBladePolyline (2 to
  /// core::kMaxBladePoints finite points, total length >= core::kMinBladeLength) and every point
  /// within kMaxBladeReach of the tool origin.
  /// @throws std::invalid_argument naming `name`.
  static void validateBlade(const std::string& name, const Eigen::Matrix3Xd& blade);

 private:
  void onPose(const geometry_msgs::PoseStamped::ConstPtr& msg);
  void onActivate(const std_msgs::Bool::ConstPtr& msg);
  bool onSetBlade(surgical_sim::SetBlade::Request& req, surgical_sim::SetBlade::Response& res);

  Eigen::Matrix3Xd blade_T_;  ///< blade polyline in the tool frame [m], 3 x k
  double max_tool_distance_ = 5.0;
  double max_step_ = 0.1;
  bool active_ = false;
  bool has_previous_ = false;
  Eigen::Matrix3Xd previous_F_;  ///< blade at the previous pose, in frame previous_frame_ [m]
  std::string previous_frame_;
  ros::Time previous_stamp_;
  ros::Subscriber pose_sub_, activate_sub_;
  ros::Publisher sweep_pub_;
  ros::ServiceServer set_blade_srv_;
};

}  // namespace surgical_sim::ros_layer
