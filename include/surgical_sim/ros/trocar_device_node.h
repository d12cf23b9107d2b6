#pragma once

#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <array>
#include <string>

#include "surgical_sim/ContactModel.h"
#include "surgical_sim/SetTrocarLimits.h"
#include "surgical_sim/core/haptics/haptic_loop.h"

namespace surgical_sim::ros_layer {

/// Everything trocar_device reads from its private parameters, validated.
struct TrocarDeviceSettings {
  core::HapticRendererConfig renderer;  ///< chain, drives, limits, contact, coupling, X_WF, rate
  int realtime_priority = 0;            ///< SCHED_FIFO priority of the loop thread, 0 = none
  double publish_rate = 100.0;          ///< joint_states / motor_effort / rendered_wrench rate [Hz]
  double stats_rate = 1.0;              ///< trocar/loop_stats rate [Hz]
  double pose_rate = 0.0;               ///< extra periodic tool/pose rate [Hz]; 0: only per command
  std::string world_frame;   ///< fixed frame W of tool/pose, rendered_wrench, contact models
  std::string trocar_frame;  ///< frame F at the fulcrum (URDF base link)
  std::string joint_prefix;  ///< URDF joint names are <prefix>pitch, <prefix>yaw, ...
  /// Broadcast the static tf world -> trocar from the pose parameters: true unless the URDF holds
  /// the fixed joint world -> trocar (a scene URDF), whose tf robot_state_publisher broadcasts.
  bool publish_trocar_tf = true;
};

/// Reads and validates the private parameters of trocar_device (see TrocarDeviceNode).
/// @throws std::invalid_argument naming the parameter (e.g. "~stale_age"), unit and range, or the
/// URDF problem (see core::readTrocarUrdf).
TrocarDeviceSettings loadTrocarDeviceSettings(const ros::NodeHandle& pnh);

/// ROS wrapper of core::HapticLoop: the 5-DoF active trocar (node `trocar_device`).
///
/// The operator's hand is a stiff position source: trocar/joint_command (JointState positions by
/// URDF joint name, [rad] or [m]) sets the device joints; the 1 kHz loop evaluates the latest
/// tissue/contact_model at the tool tip and renders it through virtual coupling, passivity
/// control, tau = J^T f and saturation. Every joint command publishes the commanded tool-tip pose
/// on tool/pose (PoseStamped in ~world_frame, stamped like the command, or now if unstamped), so
/// a lockstep tissue_simulator steps once per command. A contact model is stamped with its
/// receipt time on the loop clock: its age is the time since it arrived.
///
/// The device model (joint chain, position and effort limits, joint friction) comes from the
/// trocar's URDF: ~urdf_file if set, else robot_description (found with searchParam, so a node in
/// namespace T reads the global scene URDF). ~trocar_frame names its base link, ~joint_prefix its
/// joints (<prefix>pitch ... <prefix>grip) and tip link (<prefix>tool_tip). Gear ratios, rotor
/// inertias and encoder steps are the prototype's (core::chendebPrototypeMotors). Run-time
/// narrowing of the pitch/yaw limits: service trocar/set_limits.
///
/// Private parameters (units; range; default):
///   ~rate [Hz; 100..20000; 1000]          haptic loop rate
///   ~publish_rate [Hz; (0, 1000]; 100]    joint_states, trocar/motor_effort, rendered_wrench
///   ~stats_rate [Hz; (0, 100]; 1]         trocar/loop_stats
///   ~pose_rate [Hz; [0, 1000]; 0]         periodic tool/pose in addition to one per command
///   ~stale_age [s; (0, 10]; 0.1]          contact models older than this are stale
///   ~stale_policy [fade|hold; fade]       stale model: fade the force to zero, or hold it
///   ~fade_time [s; [0, 10]; 0.05]         fade duration of the stale force
///   ~coupling_stiffness [N/m; (0, 1e6]; 3000], ~coupling_damping [N s/m; [0, 1e4]; 2]
///   ~passivity [bool; true]               passivity controller on/off
///   ~urdf_file [path; unset]              trocar URDF instead of robot_description
///   ~x ~y ~z [m; |.| <= 10; 0 0 0.2]      fulcrum position in ~world_frame, only when the URDF
///                                         has no fixed joint ~world_frame -> ~trocar_frame
///   ~roll ~pitch ~yaw [rad; [-2pi, 2pi]; pi 0 0]  orientation of F in W (fixed-axis rpy); the
///                                         default points the cannula (z_F) straight down
///   ~realtime_priority [-; 0..99; 0]      SCHED_FIFO priority of the loop thread (0: none)
///   ~world_frame [world], ~trocar_frame [trocar], ~joint_prefix [trocar_]
/// Without that fixed joint in the URDF the node broadcasts the static tf ~world_frame ->
/// ~trocar_frame from the pose parameters.
class TrocarDeviceNode {
 public:
  /// @throws std::invalid_argument if a parameter is invalid (main exits naming it).
  TrocarDeviceNode(ros::NodeHandle& nh, ros::NodeHandle& pnh);

 private:
  void onJointCommand(const sensor_msgs::JointState::ConstPtr& msg);
  void onContactModel(const surgical_sim::ContactModel::ConstPtr& msg);
  void onPublishTimer();
  void onStatsTimer();
  bool onHome(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool onSetLimits(surgical_sim::SetTrocarLimits::Request& req,
                   surgical_sim::SetTrocarLimits::Response& res);
  /// Hands command_ to the loop and publishes the tool-tip pose it gives, stamped `stamp`.
  void applyCommand(const ros::Time& stamp);
  /// Index of a URDF joint name in joint_names_, or -1.
  int jointIndex(const std::string& name) const;

  TrocarDeviceSettings settings_;
  core::TrocarKinematics kinematics_;
  /// Node-side copy of the device: clamps commands (to name the joints beyond their limits) and
  /// quantizes them for tool/pose exactly as the loop does. Its limits follow the loop's.
  core::TrocarDevice device_;
  core::HapticLoop loop_;
  std::array<std::string, core::kTrocarJointCount> joint_names_;
  core::TrocarJointVector command_ = core::TrocarJointVector::Zero();  ///< [rad, m], clamped
  bool last_model_in_contact_ = false;  ///< staleness is worth a warning only in contact

  ros::Subscriber command_sub_, contact_sub_;
  ros::Publisher joint_states_pub_, pose_pub_, effort_pub_, wrench_pub_, stats_pub_;
  ros::ServiceServer home_srv_, limits_srv_;
  ros::WallTimer publish_timer_, stats_timer_, pose_timer_;
  tf2_ros::StaticTransformBroadcaster static_broadcaster_;
};

}  // namespace surgical_sim::ros_layer
