#pragma once

#include <geometry_msgs/PointStamped.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Core>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "surgical_sim/FollowPath.h"
#include "surgical_sim/SetTarget.h"
#include "surgical_sim/core/robot/continuum_robot_model.h"
#include "surgical_sim/core/robot/continuum_robot_urdf.h"
#include "surgical_sim/core/robot/inverse_controller.h"

namespace surgical_sim::ros_layer {

/// ROS wrapper of core::InverseController on the reduced continuum-robot model (node
/// `continuum_robot_controller`). Parameters (private; all strict, see parameters.h):
///   ~config [string; package config/continuum_robot.yaml]  robot description file
///   ~robot [string; trunk]             robot key in ~config (trunk | cable)
///   ~rate [Hz; (0, 1000]; 10]          control rate of paths and streamed targets
///   ~base_frame [string; robot_base]   frame of the model (backbone along +x)
///   ~link_prefix [string; vertebra_]   tf child frames <prefix>1 .. <prefix>n (URDF link names)
///   ~tip_frame [string; robot_tip]     tf child of <prefix>n at the tip rigid node (identity)
///   ~tolerance [m; (0, 1]; 1e-4]       default effector tolerance
///   ~max_iterations [-; 1..1000; 30]   default iterations of set_target
///   ~step_iterations [-; 1..1000; 5]   iterations per control step on a path/stream
/// Bad parameters or an invalid robot description throw std::invalid_argument naming the
/// parameter (main exits with it). Targets in another frame are resolved with tf2.
/// continuum_robot/set_target accepts at most kMaxIterations iterations (invalid_request
/// otherwise). continuum_robot/reset runs on its own thread: it answers during a long set_target
/// (or control step) and interrupts it before its next iteration; set_target then answers status
/// "interrupted" with the last iterate. On shutdown (SIGINT) a running solve stops the same way.
class ContinuumRobotNode {
 public:
  ContinuumRobotNode(ros::NodeHandle& nh, ros::NodeHandle& pnh);

  /// Most iterations of one set_target request (and of ~max_iterations) [-].
  static constexpr int kMaxIterations = 1000;

 private:
  /// Target point resolved to the base frame [m]; false with `status`/`message` set if impossible.
  bool toBaseFrame(const std::string& frame, const Eigen::Vector3d& p_F, Eigen::Vector3d& p_B,
                   std::string& status, std::string& message);
  void onTimer();
  void onStreamTarget(const geometry_msgs::PointStamped::ConstPtr& msg);
  bool onSetTarget(surgical_sim::SetTarget::Request& req, surgical_sim::SetTarget::Response& res);
  bool onFollowPath(surgical_sim::FollowPath::Request& req,
                    surgical_sim::FollowPath::Response& res);
  bool onReset(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  /// Publishes continuum_robot/actuation for the last result.
  void publishActuation(const ros::Time& stamp);
  /// Publishes continuum_robot/shape and the tf of every vertebra.
  void publishShape(const ros::Time& stamp);

  /// Guards the model, the controller, result_ and the path / stream state: held by every
  /// callback that solves or publishes; continuum_robot/reset raises cancel_ to get it quickly.
  std::mutex robot_mutex_;
  std::atomic<bool> cancel_{false};  ///< asks a running solve to stop (checked per iteration)
  std::unique_ptr<core::ContinuumRobotModel> model_;
  std::unique_ptr<core::InverseController> controller_;
  core::InverseResult result_;
  core::ContinuumRobotFrames frames_;  ///< tf frames (the links of its generated URDF)
  double rate_ = 10.0;
  double tolerance_ = 1e-4;
  int max_iterations_ = 30;
  int step_iterations_ = 5;

  std::vector<Eigen::Vector3d> path_;  ///< remaining path targets [m], base frame
  size_t path_index_ = 0;
  bool streaming_ = false;  ///< a continuum_robot/target is being tracked
  Eigen::Vector3d stream_target_ = Eigen::Vector3d::Zero();

  ros::Publisher actuation_pub_, shape_pub_;
  ros::Subscriber target_sub_;
  ros::ServiceServer set_target_srv_, follow_path_srv_, reset_srv_;
  ros::Timer timer_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster broadcaster_;
  ros::CallbackQueue control_queue_;  ///< continuum_robot/reset
  /// Serves control_queue_; declared last so it stops first when the node is destroyed.
  ros::AsyncSpinner control_spinner_;
};

}  // namespace surgical_sim::ros_layer
