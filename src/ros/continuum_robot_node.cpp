#include "surgical_sim/ros/continuum_robot_node.h"

#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <ros/package.h>
#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "surgical_sim/Actuation.h"
#include "surgical_sim/core/robot/compliance_cache.h"
#include "surgical_sim/core/robot/continuum_robot_loader.h"
#include "surgical_sim/core/robot/resample_polyline.h"
#include "surgical_sim/ros/conversions.h"
#include "surgical_sim/ros/parameters.h"

namespace surgical_sim::ros_layer {
namespace {

constexpr const char* kName = "continuum_robot_controller";

}  // namespace

ContinuumRobotNode::ContinuumRobotNode(ros::NodeHandle& nh, ros::NodeHandle& pnh)
    : tf_listener_(tf_buffer_), control_spinner_(1, &control_queue_) {
  const std::string config = stringParam(
      pnh, "config", ros::package::getPath("surgical_sim") + "/config/continuum_robot.yaml");
  const std::string robot = stringParam(pnh, "robot", "trunk");
  rate_ = numberParam(pnh, "rate", 10.0, {0.0, 1000.0, true}, "Hz");
  frames_.base = stringParam(pnh, "base_frame", frames_.base);
  frames_.link_prefix = stringParam(pnh, "link_prefix", frames_.link_prefix);
  frames_.tip = stringParam(pnh, "tip_frame", frames_.tip);
  tolerance_ = numberParam(pnh, "tolerance", 1e-4, {0.0, 1.0, true}, "m");
  max_iterations_ = intParam(pnh, "max_iterations", 30, 1, kMaxIterations, "");
  step_iterations_ = intParam(pnh, "step_iterations", 5, 1, 1000, "");

  core::ContinuumRobotDescription description;
  try {
    description = core::loadContinuumRobot(config, robot);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("~robot = '" + robot + "' / ~config = '" + config +
                                "': " + e.what());
  }
  // Progress bar of the offline condensation (stderr) when not cached.
  const core::SectionCompliances compliances =
      core::computeSectionCompliances(description, core::ComplianceCache::defaultDirectory());
  model_ = std::make_unique<core::ContinuumRobotModel>(description, compliances);
  controller_ =
      std::make_unique<core::InverseController>(*model_, core::InverseControllerSettings{});
  controller_->setCancelCheck([this] { return cancel_.load() || ros::isShuttingDown(); });
  result_.actuation = controller_->actuation();

  actuation_pub_ = nh.advertise<surgical_sim::Actuation>("continuum_robot/actuation", 100);
  shape_pub_ = nh.advertise<geometry_msgs::PoseArray>("continuum_robot/shape", 10, true);
  target_sub_ =
      nh.subscribe("continuum_robot/target", 10, &ContinuumRobotNode::onStreamTarget, this);
  set_target_srv_ =
      nh.advertiseService("continuum_robot/set_target", &ContinuumRobotNode::onSetTarget, this);
  follow_path_srv_ =
      nh.advertiseService("continuum_robot/follow_path", &ContinuumRobotNode::onFollowPath, this);
  // reset is served by its own thread: it answers during a long set_target and interrupts it.
  ros::NodeHandle control_nh(nh);
  control_nh.setCallbackQueue(&control_queue_);
  reset_srv_ =
      control_nh.advertiseService("continuum_robot/reset", &ContinuumRobotNode::onReset, this);
  timer_ = nh.createTimer(ros::Duration(1.0 / rate_), [this](const auto&) { onTimer(); });
  publishShape(ros::Time::now());
  ROS_INFO_NAMED(
      kName,
      "robot '%s': %d vertebrae, %d actuators, sections condensed in %.2f s (%d cached), "
      "control at %.1f Hz in frame %s",
      robot.c_str(), description.num_vertebrae, model_->numActuators(), compliances.seconds,
      compliances.cache_hits, rate_, frames_.base.c_str());
  control_spinner_.start();
}

bool ContinuumRobotNode::toBaseFrame(const std::string& frame, const Eigen::Vector3d& p_F,
                                     Eigen::Vector3d& p_B, std::string& status,
                                     std::string& message) {
  if (!p_F.allFinite()) {
    status = core::toString(core::InverseStatus::InvalidTarget);
    message = "target has a NaN or Inf coordinate";
    return false;
  }
  if (frame.empty() || frame == frames_.base) {
    p_B = p_F;
    return true;
  }
  try {
    const auto t =
        tf_buffer_.lookupTransform(frames_.base, frame, ros::Time(0), ros::Duration(0.2));
    p_B = tf2::transformToEigen(t) * p_F;
    return true;
  } catch (const tf2::TransformException& e) {
    status = "unknown_frame";
    message = "cannot resolve frame '" + frame + "' to '" + frames_.base + "': " + e.what();
    return false;
  }
}

void ContinuumRobotNode::onTimer() {
  std::lock_guard<std::mutex> lock(robot_mutex_);
  const ros::Time stamp = ros::Time::now();
  if (path_index_ < path_.size()) {
    controller_->solveTarget(path_[path_index_++], tolerance_, step_iterations_, result_);
    publishActuation(stamp);
  } else if (streaming_) {
    controller_->solveTarget(stream_target_, tolerance_, step_iterations_, result_);
    publishActuation(stamp);
  }
  publishShape(stamp);
}

void ContinuumRobotNode::onStreamTarget(const geometry_msgs::PointStamped::ConstPtr& msg) {
  std::string status, message;
  Eigen::Vector3d p_B;
  if (!toBaseFrame(msg->header.frame_id, toEigen(msg->point), p_B, status, message)) {
    ROS_WARN_THROTTLE_NAMED(1.0, kName, "continuum_robot/target rejected (%s): %s", status.c_str(),
                            message.c_str());
    return;
  }
  std::lock_guard<std::mutex> lock(robot_mutex_);
  path_.clear();
  path_index_ = 0;
  streaming_ = true;
  stream_target_ = p_B;
}

bool ContinuumRobotNode::onSetTarget(surgical_sim::SetTarget::Request& req,
                                     surgical_sim::SetTarget::Response& res) {
  const double tolerance = req.tolerance == 0.0 ? tolerance_ : req.tolerance;
  const uint32_t iterations =
      req.max_iterations == 0 ? static_cast<uint32_t>(max_iterations_) : req.max_iterations;
  std::lock_guard<std::mutex> lock(robot_mutex_);
  res.actuation.assign(result_.actuation.data(),
                       result_.actuation.data() + result_.actuation.size());
  if (!(std::isfinite(tolerance) && tolerance > 0.0)) {
    res.status = "invalid_request";
    res.message = "tolerance = " + std::to_string(tolerance) + " m must be finite and > 0";
    return true;
  }
  if (iterations > static_cast<uint32_t>(kMaxIterations)) {
    res.status = "invalid_request";
    res.message = "max_iterations = " + std::to_string(iterations) +
                  " must be <= " + std::to_string(kMaxIterations) + " (0: ~max_iterations)";
    return true;
  }
  Eigen::Vector3d p_B;
  if (!toBaseFrame(req.target.header.frame_id, toEigen(req.target.point), p_B, res.status,
                   res.message))
    return true;
  path_.clear();
  path_index_ = 0;
  streaming_ = false;
  controller_->solveTarget(p_B, tolerance, static_cast<int>(iterations), result_);
  res.actuation.assign(result_.actuation.data(),
                       result_.actuation.data() + result_.actuation.size());
  res.effector_error = result_.effector_error;
  res.iterations = static_cast<uint32_t>(result_.iterations);
  res.status = core::toString(result_.status);
  res.message = result_.status == core::InverseStatus::Interrupted
                    ? std::string("interrupted by ") +
                          (ros::isShuttingDown() ? "shutdown" : "continuum_robot/reset") +
                          " after " + std::to_string(result_.iterations) + " iterations"
                    : result_.message;
  const ros::Time stamp = ros::Time::now();
  publishActuation(stamp);
  publishShape(stamp);
  return true;
}

bool ContinuumRobotNode::onFollowPath(surgical_sim::FollowPath::Request& req,
                                      surgical_sim::FollowPath::Response& res) {
  if (req.points.empty() || !(std::isfinite(req.speed) && req.speed > 0.0)) {
    res.message = "need at least one point and a finite speed > 0 m/s";
    return true;
  }
  std::vector<Eigen::Vector3d> points;
  std::string status;
  for (const geometry_msgs::Point& p : req.points) {
    points.emplace_back();
    if (!toBaseFrame(req.frame_id, toEigen(p), points.back(), status, res.message)) return true;
  }
  double length = 0.0;  // [m]
  for (size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  if (length * rate_ / req.speed > 1e6) {
    res.message = "path would take more than 1e6 control steps; raise the speed";
    return true;
  }
  std::lock_guard<std::mutex> lock(robot_mutex_);
  path_ = core::resamplePolyline(points, req.speed / rate_);
  path_index_ = 0;
  streaming_ = false;
  res.accepted = true;
  res.steps = static_cast<uint32_t>(path_.size());
  res.duration = path_.size() / rate_;
  char message[96];
  std::snprintf(message, sizeof message, "following %zu targets at %.3g Hz (%.3g s)", path_.size(),
                rate_, res.duration);
  res.message = message;
  return true;
}

bool ContinuumRobotNode::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  cancel_ = true;  // a running solve stops before its next iteration and releases the lock
  std::lock_guard<std::mutex> lock(robot_mutex_);
  cancel_ = false;
  path_.clear();
  path_index_ = 0;
  streaming_ = false;
  controller_->reset();
  result_.actuation = controller_->actuation();
  result_.effector_error = 0.0;
  publishShape(ros::Time::now());
  res.success = true;
  res.message = "rest shape, actuation at its lower bounds";
  return true;
}

void ContinuumRobotNode::publishActuation(const ros::Time& stamp) {
  surgical_sim::Actuation msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frames_.base;
  const int chambers = static_cast<int>(model_->description().chambers.size());
  for (int a = 0; a < model_->numActuators(); ++a) {
    msg.names.push_back(model_->actuators()[a]->name());
    msg.values.push_back(result_.actuation[a]);
    msg.units.push_back(a < chambers ? "Pa" : "N");
  }
  msg.status = core::toString(result_.status);
  msg.effector_error = result_.effector_error;
  actuation_pub_.publish(msg);
}

void ContinuumRobotNode::publishShape(const ros::Time& stamp) {
  geometry_msgs::PoseArray shape;
  shape.header.stamp = stamp;
  shape.header.frame_id = frames_.base;
  std::vector<geometry_msgs::TransformStamped> transforms;
  const auto& nodes = model_->nodes();
  for (size_t k = 0; k < nodes.size(); ++k) {
    const Eigen::Isometry3d X_BN =
        Eigen::Translation3d(nodes[k].p_BN) * Eigen::Isometry3d(nodes[k].q_BN);
    shape.poses.push_back(toPoseMsg(X_BN));
    if (k == 0) continue;  // the base rigid node is the fixed robot_base itself
    geometry_msgs::TransformStamped t = tf2::eigenToTransform(X_BN);
    t.header = shape.header;
    t.child_frame_id = frames_.rigidNode(static_cast<int>(k));
    transforms.push_back(t);
  }
  geometry_msgs::TransformStamped tip;  // identity: the tip is the last rigid node
  tip.header.stamp = stamp;
  tip.header.frame_id = transforms.back().child_frame_id;
  tip.child_frame_id = frames_.tip;
  tip.transform.rotation.w = 1.0;
  transforms.push_back(tip);
  shape_pub_.publish(shape);
  broadcaster_.sendTransform(transforms);
}

}  // namespace surgical_sim::ros_layer
