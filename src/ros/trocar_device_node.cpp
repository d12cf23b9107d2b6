#include "surgical_sim/ros/trocar_device_node.h"

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <tf2_eigen/tf2_eigen.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "surgical_sim/LoopStats.h"
#include "surgical_sim/core/common/text_file.h"
#include "surgical_sim/core/haptics/trocar_urdf.h"
#include "surgical_sim/ros/conversions.h"
#include "surgical_sim/ros/parameters.h"

namespace surgical_sim::ros_layer {
namespace {

constexpr char kLog[] = "trocar_device";
constexpr double kDeg = M_PI / 180.0;
constexpr double kStatsWindowSeconds = 5.0;  ///< loop periods kept for mean / p99 / max [s]

const char* jointUnit(int joint) { return joint == core::kTrocarInsertion ? "m" : "rad"; }

/// The first name that appears more than once in `names`, or nullptr.
const std::string* duplicatedName(const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t k = i + 1; k < names.size(); ++k)
      if (names[i] == names[k]) return &names[i];
  return nullptr;
}

/// The trocar URDF: the file ~urdf_file if set, else the text of robot_description (searched up
/// from the node's namespace, so a namespaced node finds the global one).
std::string loadTrocarUrdfText(const ros::NodeHandle& pnh) {
  if (pnh.hasParam("urdf_file")) {
    const std::string path = stringParam(pnh, "urdf_file", "");
    try {
      return core::readTextFile(path);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("~urdf_file: ") + e.what());
    }
  }
  std::string key, text;
  if (!pnh.searchParam("robot_description", key))
    throw std::invalid_argument(
        "no trocar URDF: set robot_description (searched up from the node's namespace) or "
        "~urdf_file");
  if (!pnh.getParam(key, text) || text.empty())
    throw std::invalid_argument(key + " must be a non-empty string holding the URDF");
  return text;
}

}  // namespace

TrocarDeviceSettings loadTrocarDeviceSettings(const ros::NodeHandle& pnh) {
  constexpr double kTwoPi = 2.0 * M_PI;
  for (const char* removed : {"pitch_limit_deg", "yaw_limit_deg"})
    if (pnh.hasParam(removed))
      throw std::invalid_argument(std::string("~") + removed +
                                  " is not a parameter: the joint limits come from the URDF "
                                  "<limit> elements; narrow them at run time with "
                                  "trocar/set_limits");
  TrocarDeviceSettings s;
  s.world_frame = stringParam(pnh, "world_frame", "world");
  s.trocar_frame = stringParam(pnh, "trocar_frame", "trocar");
  s.joint_prefix = stringParam(pnh, "joint_prefix", "trocar_", true);
  core::TrocarUrdfNames names;
  names.base_link = s.trocar_frame;
  names.joint_prefix = s.joint_prefix;
  names.world_link = s.world_frame;
  const core::TrocarUrdf urdf = core::readTrocarUrdf(loadTrocarUrdfText(pnh), names);

  core::HapticRendererConfig& c = s.renderer;
  c.chain = urdf.chain;
  c.device = core::makeTrocarDeviceConfig(urdf, core::chendebPrototypeMotors());
  c.rate_hz = numberParam(pnh, "rate", 1000.0, {100.0, 20000.0}, "Hz");
  c.contact.max_age = numberParam(pnh, "stale_age", 0.1, {0.0, 10.0, true}, "s");
  c.contact.fade_time = numberParam(pnh, "fade_time", 0.05, {0.0, 10.0}, "s");
  c.contact.stale_policy = choiceParam(pnh, "stale_policy", "fade", {"fade", "hold"}) == "fade"
                               ? core::StalePolicy::Fade
                               : core::StalePolicy::Hold;
  c.coupling.stiffness = numberParam(pnh, "coupling_stiffness", 3000.0, {0.0, 1e6, true}, "N/m");
  c.coupling.damping = numberParam(pnh, "coupling_damping", 2.0, {0.0, 1e4}, "N s/m");
  c.passivity.control_enabled = boolParam(pnh, "passivity", true);

  // Pose of the trocar frame F (fulcrum, z along the cannula) in W: the URDF's fixed joint
  // world -> trocar if it has one, else the pose parameters (fixed-axis roll-pitch-yaw).
  static const char* const kPoseParams[] = {"x", "y", "z", "roll", "pitch", "yaw"};
  s.publish_trocar_tf = !urdf.X_WF.has_value();
  if (urdf.X_WF) {
    for (const char* name : kPoseParams)
      if (pnh.hasParam(name))
        throw std::invalid_argument(
            std::string("~") + name + " is set but the URDF places '" + s.trocar_frame + "' in '" +
            s.world_frame + "' (fixed joint '" + s.world_frame + "' -> '" + s.trocar_frame +
            "'): the fulcrum pose has one source, remove ~x ~y ~z ~roll ~pitch ~yaw");
    c.X_WF = *urdf.X_WF;
  } else {
    Eigen::Vector3d p_WF;
    p_WF.x() = numberParam(pnh, "x", 0.0, {-10.0, 10.0}, "m");
    p_WF.y() = numberParam(pnh, "y", 0.0, {-10.0, 10.0}, "m");
    p_WF.z() = numberParam(pnh, "z", 0.2, {-10.0, 10.0}, "m");
    const double roll = numberParam(pnh, "roll", M_PI, {-kTwoPi, kTwoPi}, "rad");
    const double pitch = numberParam(pnh, "pitch", 0.0, {-kTwoPi, kTwoPi}, "rad");
    const double yaw = numberParam(pnh, "yaw", 0.0, {-kTwoPi, kTwoPi}, "rad");
    c.X_WF = Eigen::Translation3d(p_WF) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
             Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
             Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  }

  s.realtime_priority = intParam(pnh, "realtime_priority", 0, 0, 99, "");
  s.publish_rate = numberParam(pnh, "publish_rate", 100.0, {0.0, 1000.0, true}, "Hz");
  s.stats_rate = numberParam(pnh, "stats_rate", 1.0, {0.0, 100.0, true}, "Hz");
  s.pose_rate = numberParam(pnh, "pose_rate", 0.0, {0.0, 1000.0}, "Hz");
  core::validateHapticRendererConfig(c);
  return s;
}

TrocarDeviceNode::TrocarDeviceNode(ros::NodeHandle& nh, ros::NodeHandle& pnh)
    : settings_(loadTrocarDeviceSettings(pnh)),
      kinematics_(settings_.renderer.chain),
      device_(settings_.renderer.device),
      loop_(settings_.renderer,
            static_cast<std::size_t>(kStatsWindowSeconds * settings_.renderer.rate_hz),
            settings_.realtime_priority) {
  for (int j = 0; j < core::kTrocarJointCount; ++j)
    joint_names_[static_cast<std::size_t>(j)] = settings_.joint_prefix + core::trocarJointName(j);

  if (settings_.publish_trocar_tf) {
    geometry_msgs::TransformStamped t = tf2::eigenToTransform(settings_.renderer.X_WF);
    t.header.stamp = ros::Time::now();
    t.header.frame_id = settings_.world_frame;
    t.child_frame_id = settings_.trocar_frame;
    static_broadcaster_.sendTransform(t);
  }

  joint_states_pub_ = nh.advertise<sensor_msgs::JointState>("joint_states", 10);
  pose_pub_ = nh.advertise<geometry_msgs::PoseStamped>("tool/pose", 1000);
  effort_pub_ = nh.advertise<sensor_msgs::JointState>("trocar/motor_effort", 100);
  wrench_pub_ = nh.advertise<geometry_msgs::WrenchStamped>("trocar/rendered_wrench", 100);
  stats_pub_ = nh.advertise<surgical_sim::LoopStats>("trocar/loop_stats", 10);
  command_sub_ = nh.subscribe("trocar/joint_command", 1000, &TrocarDeviceNode::onJointCommand, this,
                              ros::TransportHints().tcpNoDelay());
  contact_sub_ = nh.subscribe("tissue/contact_model", 100, &TrocarDeviceNode::onContactModel, this,
                              ros::TransportHints().tcpNoDelay());
  home_srv_ = nh.advertiseService("trocar/home", &TrocarDeviceNode::onHome, this);
  limits_srv_ = nh.advertiseService("trocar/set_limits", &TrocarDeviceNode::onSetLimits, this);

  loop_.setJointCommand(command_);
  loop_.start();
  publish_timer_ = nh.createWallTimer(ros::WallDuration(1.0 / settings_.publish_rate),
                                      [this](const auto&) { onPublishTimer(); });
  stats_timer_ = nh.createWallTimer(ros::WallDuration(1.0 / settings_.stats_rate),
                                    [this](const auto&) { onStatsTimer(); });
  if (settings_.pose_rate > 0.0)
    pose_timer_ = nh.createWallTimer(ros::WallDuration(1.0 / settings_.pose_rate),
                                     [this](const auto&) { applyCommand(ros::Time::now()); });
  if (settings_.realtime_priority > 0 && !loop_.realtimeGranted())
    ROS_WARN_NAMED(kLog, "~realtime_priority %d refused (needs CAP_SYS_NICE / rtprio limits)",
                   settings_.realtime_priority);
  const Eigen::Vector3d p_WF = settings_.renderer.X_WF.translation();
  ROS_INFO_NAMED(kLog,
                 "haptic loop at %.0f Hz, fulcrum at (%.3f, %.3f, %.3f) m in '%s', pitch/yaw "
                 "limits +-%.1f/+-%.1f deg, contact models stale after %.3f s",
                 settings_.renderer.rate_hz, p_WF.x(), p_WF.y(), p_WF.z(),
                 settings_.world_frame.c_str(), settings_.renderer.device.pitch_limit / kDeg,
                 settings_.renderer.device.yaw_limit / kDeg, settings_.renderer.contact.max_age);
}

int TrocarDeviceNode::jointIndex(const std::string& name) const {
  for (int j = 0; j < core::kTrocarJointCount; ++j)
    if (joint_names_[static_cast<std::size_t>(j)] == name) return j;
  return -1;
}

void TrocarDeviceNode::onJointCommand(const sensor_msgs::JointState::ConstPtr& msg) {
  if (msg->position.size() != msg->name.size()) {
    ROS_WARN_THROTTLE_NAMED(1.0, kLog,
                            "trocar/joint_command ignored: %zu names but %zu positions (positions "
                            "are required, by joint name)",
                            msg->name.size(), msg->position.size());
    return;
  }
  if (const std::string* twice = duplicatedName(msg->name)) {
    ROS_WARN_THROTTLE_NAMED(1.0, kLog,
                            "trocar/joint_command ignored: joint '%s' appears more than once "
                            "(each joint at most once per command)",
                            twice->c_str());
    return;
  }
  core::TrocarJointVector q = command_;
  for (std::size_t i = 0; i < msg->name.size(); ++i) {
    const int j = jointIndex(msg->name[i]);
    if (j < 0) {
      ROS_WARN_THROTTLE_NAMED(1.0, kLog,
                              "trocar/joint_command: unknown joint '%s' ignored (joints: %s, %s, "
                              "%s, %s, %s)",
                              msg->name[i].c_str(), joint_names_[0].c_str(),
                              joint_names_[1].c_str(), joint_names_[2].c_str(),
                              joint_names_[3].c_str(), joint_names_[4].c_str());
    } else if (!std::isfinite(msg->position[i])) {
      ROS_WARN_THROTTLE_NAMED(1.0, kLog,
                              "trocar/joint_command: non-finite position for joint '%s'; holding "
                              "its previous command %.6g %s",
                              msg->name[i].c_str(), command_[j], jointUnit(j));
    } else {
      q[j] = msg->position[i];
    }
  }
  core::TrocarJointVector clamped = q;
  if (device_.clampToLimits(clamped)) {
    for (int j = 0; j < core::kTrocarJointCount; ++j) {
      if (j == core::kTrocarSpin || clamped[j] == q[j]) continue;  // spin wraps, never clamps
      ROS_WARN_THROTTLE_NAMED(1.0, kLog,
                              "trocar/joint_command: joint '%s' command %.6g %s is beyond its "
                              "limits; clamped to %.6g %s",
                              joint_names_[static_cast<std::size_t>(j)].c_str(), q[j], jointUnit(j),
                              clamped[j], jointUnit(j));
    }
  }
  command_ = clamped;
  applyCommand(msg->header.stamp.isZero() ? ros::Time::now() : msg->header.stamp);
}

void TrocarDeviceNode::applyCommand(const ros::Time& stamp) {
  loop_.setJointCommand(command_);
  // The pose the loop will measure: encoder reading of the command, forward kinematics, F -> W.
  geometry_msgs::PoseStamped pose;
  pose.header.stamp = stamp;
  pose.header.frame_id = settings_.world_frame;
  pose.pose =
      toPoseMsg(settings_.renderer.X_WF * kinematics_.toolTipPose(device_.quantize(command_)));
  pose_pub_.publish(pose);
}

void TrocarDeviceNode::onContactModel(const surgical_sim::ContactModel::ConstPtr& msg) {
  const std::string& frame = msg->header.frame_id;
  if (!frame.empty() && frame != settings_.world_frame) {
    ROS_WARN_THROTTLE_NAMED(1.0, kLog,
                            "tissue/contact_model in frame '%s' ignored: expected '%s' (~world_"
                            "frame)",
                            frame.c_str(), settings_.world_frame.c_str());
    return;
  }
  core::LocalContactSample s;
  s.stamp = loop_.now();  // receipt time on the loop clock: the age counts from arrival
  s.p0_W = toEigen(msg->point);
  s.f0_W = toEigen(msg->force);
  s.K_W = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(msg->stiffness.data());
  if (!s.p0_W.allFinite() || !s.f0_W.allFinite() || !s.K_W.allFinite()) {
    ROS_WARN_THROTTLE_NAMED(1.0, kLog,
                            "tissue/contact_model with NaN/Inf ignored; the previous model "
                            "stays (and goes stale)");
    return;
  }
  loop_.setContactModel(s);
  last_model_in_contact_ = msg->in_contact;
}

void TrocarDeviceNode::onPublishTimer() {
  const core::HapticOutput out = loop_.latestOutput();
  const ros::Time stamp = ros::Time::now();
  sensor_msgs::JointState joints;
  joints.header.stamp = stamp;
  joints.name.assign(joint_names_.begin(), joint_names_.end());
  joints.position.assign(out.q_measured.data(), out.q_measured.data() + core::kTrocarJointCount);
  joint_states_pub_.publish(joints);
  // Saturated joint efforts [N m; insertion N] the motors apply: what the surgeon feels.
  joints.effort.assign(out.effort.data(), out.effort.data() + core::kTrocarJointCount);
  effort_pub_.publish(joints);

  geometry_msgs::WrenchStamped wrench;  // force on the tool, applied at the tool tip, in W
  wrench.header.stamp = stamp;
  wrench.header.frame_id = settings_.world_frame;
  wrench.wrench.force = toVector3Msg(out.f_rendered_W);
  wrench_pub_.publish(wrench);

  if (out.contact_status == core::ContactStatus::Stale && last_model_in_contact_)
    ROS_WARN_THROTTLE_NAMED(
        1.0, kLog, "tissue/contact_model is stale (%.3f s old > ~stale_age %.3f s): force %s",
        out.contact_age, settings_.renderer.contact.max_age,
        settings_.renderer.contact.stale_policy == core::StalePolicy::Fade ? "fades to zero"
                                                                           : "held");
  if (out.saturation.saturated)
    ROS_WARN_THROTTLE_NAMED(1.0, kLog, "motor efforts saturated: scaled by %.3f",
                            out.saturation.scale);
}

void TrocarDeviceNode::onStatsTimer() {
  const core::LoopStatistics s = loop_.statistics();
  surgical_sim::LoopStats msg;
  msg.header.stamp = ros::Time::now();
  msg.ticks = s.ticks;
  msg.missed_ticks = s.missed_ticks;
  msg.samples = static_cast<std::uint32_t>(s.samples);
  msg.nominal_period = s.nominal_period;
  msg.period_mean = s.period_mean;
  msg.period_p99 = s.period_p99;
  msg.period_max = s.period_max;
  msg.max_deviation = s.max_deviation;
  msg.realtime_granted = loop_.realtimeGranted();
  stats_pub_.publish(msg);
}

bool TrocarDeviceNode::onHome(std_srvs::Trigger::Request& /*req*/,
                              std_srvs::Trigger::Response& res) {
  command_ = core::TrocarJointVector::Zero();
  loop_.requestReset();
  applyCommand(ros::Time::now());
  res.success = true;
  res.message =
      "homed: all joints commanded to 0 (tool retracted, insertion 0 m); coupling and passivity "
      "observer reset";
  ROS_INFO_NAMED(kLog, "%s", res.message.c_str());
  return true;
}

bool TrocarDeviceNode::onSetLimits(surgical_sim::SetTrocarLimits::Request& req,
                                   surgical_sim::SetTrocarLimits::Response& res) {
  try {
    loop_.setPitchYawLimits(kDeg * req.pitch_limit_deg, kDeg * req.yaw_limit_deg);
  } catch (const std::invalid_argument& e) {
    res.success = false;
    res.message = std::string("limits unchanged: ") + e.what();
    ROS_WARN_NAMED(kLog, "trocar/set_limits rejected: %s", e.what());
    return true;
  }
  device_.setPitchYawLimits(kDeg * req.pitch_limit_deg, kDeg * req.yaw_limit_deg);
  device_.clampToLimits(command_);
  applyCommand(ros::Time::now());
  res.success = true;
  res.message = "pitch limit +-" + std::to_string(req.pitch_limit_deg) + " deg, yaw limit +-" +
                std::to_string(req.yaw_limit_deg) + " deg";
  ROS_INFO_NAMED(kLog, "trocar/set_limits: %s", res.message.c_str());
  return true;
}

}  // namespace surgical_sim::ros_layer
