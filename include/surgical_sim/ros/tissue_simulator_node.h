#pragma once

#include <geometry_msgs/PoseStamped.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Bool.h>
#include <std_srvs/Empty.h>
#include <std_srvs/SetBool.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/Marker.h>

#include <Eigen/Geometry>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "surgical_sim/BladeSweep.h"
#include "surgical_sim/StepTissue.h"
#include "surgical_sim/core/scene/multi_body_simulation.h"
#include "surgical_sim/core/scene/tissue_simulation.h"
#include "surgical_sim/ros/pose_set_sync.h"
#include "surgical_sim/ros/real_time_factor.h"

namespace surgical_sim::ros_layer {

/// ROS wrapper of core::TissueSimulation (node `tissue_simulator`). Parameters (private; all
/// strict, see parameters.h):
///   ~scene [string; required]          scene YAML path
///   ~realtime [bool; true]             true: step on a wall-clock timer at the scene's dt, each
///                                      tool at its newest pose; false: lockstep (below), or
///                                      free-running without tools
///   ~steps_per_pose [-; 1..1000; 1]    lockstep steps per synchronized set of tool poses
///   ~world_frame [string; world]       frame of the wrench / contact-model outputs
///   ~tissue_frame [string; tissue]     rest frame of the organ (tf world -> tissue published)
///   ~surface_rate [Hz; (0, 1000]; 30]  rate of tissue/surface in realtime mode
///   ~max_tool_distance [m; (0, 1000]; 5]  poses farther than this from the world origin are
///                                      rejected
///   ~force_arrow_scale [m/N; (0, 10]; 0.03]  length per newton of the force arrows on
///                                      tissue/tools
/// Lockstep: the node steps once per synchronized SET of tool poses (PoseSetSync), whatever the
/// number of tools: when every tool of the scene has received a pose stamped newer than the last
/// stepped set, it moves each tool to its newest pose and steps steps_per_pose times, every output
/// stamped with the set's (newest) stamp; tissue/stats carries pose_set_stamp, burst_step and
/// burst_end. A pose with a zero stamp is stamped on receipt. A second pose of one tool before the
/// set is complete replaces the first (throttled warning: a dropped pose); a pose not newer than
/// the last set is ignored (throttled warning; tissue/reset forgets the stamps, so a replay can
/// restart); a tool that never received a pose blocks every set (named in a throttled warning
/// when another tool overruns).
/// tissue/pause interrupts a burst between two steps; un-pausing finishes it and steps a set that
/// completed meanwhile. Same poses and stamps from a reset give bit-identical outputs.
/// Tool poses that are NaN/Inf, have a zero or non-finite quaternion, lie too far or are in a
/// frame tf cannot resolve are rejected, each with its own throttled warning.
/// Subscribes cutting/blade_sweep (BladeSweep, any frame tf can resolve): each sweep is applied
/// before the next step; tissue/stats reports its cost (cut_time) and the pieces; the surface
/// marker draws cut faces in dark red.
/// Services: tissue/pause and tissue/reset run on their own thread, so they answer during a long
/// tissue/step (or lockstep burst) and interrupt it between two steps; tissue/step then answers
/// success = false, "interrupted by <pause|reset> after N steps" with steps_done = N. On
/// shutdown (SIGINT) a running request stops the same way.
/// A multi-body scene (key bodies) runs core::MultiBodySimulation with the same topics and
/// services: tissue/surface draws every organ and connective layer surface in its own colour
/// (contact nodes red), tissue/rigid_nodes the layers' rigid nodes as axes (LINE_LIST, x red,
/// y green, z blue, 4 mm), tissue/stats reports the bodies as pieces; blade sweeps are rejected.
/// Scene errors throw std::invalid_argument from the constructor (main exits naming the key); a
/// benchmark file (sweep lists, measure) is rejected naming its first benchmark key.
class TissueSimulatorNode {
 public:
  TissueSimulatorNode(ros::NodeHandle& nh, ros::NodeHandle& pnh);

  /// Most steps one tissue/step request may ask for [-].
  static constexpr unsigned kMaxStepRequest = 10000;

 private:
  struct ToolIo {
    ros::Subscriber pose_sub, grasp_sub, grip_sub;
    ros::Publisher wrench_pub, contact_pub;
    bool has_pose = false;
    Eigen::Isometry3d X_ST = Eigen::Isometry3d::Identity();  ///< last accepted tip pose
  };

  void onPose(const geometry_msgs::PoseStamped::ConstPtr& msg, int tool);
  /// Lockstep: offers a resolved pose to sync_ (warning on a stale or dropped pose, then naming
  /// the tools that never had a pose); under sim_mutex_.
  void offerPose(int tool, const ros::Time& stamp, const Eigen::Isometry3d& X_ST);
  /// Lockstep (main thread): finishes the open burst, then steps every complete pose set, until
  /// paused or interrupted.
  void runLockstep();
  void onGrasp(const std_msgs::Bool::ConstPtr& msg, int tool);
  /// Jaws from the tool's grip joint in a JointState (e.g. trocar_device's joint_states).
  void onGrip(const sensor_msgs::JointState::ConstPtr& msg, int tool);
  void onBladeSweep(const surgical_sim::BladeSweep::ConstPtr& msg);
  /// Lockstep: hands the deferred sweeps that ended before set_stamp to sim_ (under sim_mutex_).
  void requestDeferredCuts(const ros::Time& set_stamp);
  void onTimer();
  /// Steps once and publishes everything stamped `stamp`; burst_step > 0: step burst_step of the
  /// lockstep burst of set `set_stamp` (reported in tissue/stats). Needs sim_mutex_ held; returns
  /// false on a failed step.
  bool stepAndPublish(const ros::Time& stamp, bool publish_surface,
                      const ros::Time& set_stamp = ros::Time(), int burst_step = 0);
  void publishSurface(const ros::Time& stamp);
  /// surface_marker_ with its header (stamp, tissue frame) and TRIANGLE_LIST settings.
  visualization_msgs::Marker& surfaceMarker(const ros::Time& stamp);
  /// Each posed tool as a capsule (shaft cylinder + tip sphere) on tissue/tools (namespace: the
  /// tool's name), with the tissue's force on it as an arrow from the tip while in contact.
  void publishToolMarkers(const ros::Time& stamp);
  void publishTool(int tool, const ros::Time& stamp);
  /// Resolves a pose to the tissue frame; false (with a throttled warning) if impossible.
  bool toTissueFrame(const geometry_msgs::PoseStamped& msg, Eigen::Isometry3d& X_ST);
  /// Pose X_SF of frame F in the tissue frame S; false (with a throttled warning naming `what`
  /// was rejected) if unknown.
  bool frameInTissue(const std::string& frame, const char* what, Eigen::Isometry3d& X_SF);
  /// Makes running step loops stop before their next step; `reason` is a static string.
  void interrupt(const char* reason);
  /// Why a loop that started when interrupts_ was `since` must stop ("pause", "reset",
  /// "shutdown"), or nullptr to go on.
  const char* interruption(unsigned since) const;
  bool onReset(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onPause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res);
  bool onStep(surgical_sim::StepTissue::Request& req, surgical_sim::StepTissue::Response& res);
  /// The running simulation (single- or multi-body): its scene, step, time, tools and reset.
  const core::RuntimeScene& scene() const { return multi_ ? multi_->scene() : sim_->scene(); }
  int numTools() const { return static_cast<int>(scene().tools.size()); }
  core::SimulationStepStats stepSimulation() { return multi_ ? multi_->step() : sim_->step(); }
  double simulationTime() const { return multi_ ? multi_->time() : sim_->state().time; }
  void setToolPose(int tool, const Eigen::Isometry3d& X_ST);
  void setGrasp(int tool, bool closed);
  core::ContactLinearization toolContact(int tool) const {
    return multi_ ? multi_->toolContact(tool) : sim_->toolContact(tool);
  }
  /// Multi-body scene: every organ and layer surface into tissue/surface, the rigid nodes into
  /// tissue/rigid_nodes.
  void publishBodies(const ros::Time& stamp);

  /// Guards sim_, step_count_, the tools' poses, sync_ and the burst state: held for one step at
  /// a time, so tissue/reset (control thread) waits for at most the step in progress.
  std::mutex sim_mutex_;
  std::unique_ptr<core::TissueSimulation> sim_;       ///< single-body scene, else null
  std::unique_ptr<core::MultiBodySimulation> multi_;  ///< multi-body scene, else null
  Eigen::Isometry3d X_WS_ = Eigen::Isometry3d::Identity();
  std::string world_frame_, tissue_frame_;
  bool realtime_ = true;
  std::atomic<bool> paused_{false};
  std::atomic<unsigned> interrupts_{0};                ///< bumped by every pause / reset
  std::atomic<const char*> interrupt_reason_{"none"};  ///< reason of the last bump
  int steps_per_pose_ = 1;
  double max_tool_distance_ = 5.0;
  double surface_period_ = 1.0 / 30.0;
  double force_arrow_scale_ = 0.03;  ///< [m/N]
  double last_surface_wall_ = -1e9;
  double last_publish_seconds_ = 0.0;
  unsigned step_count_ = 0;
  RealTimeFactor real_time_factor_{1.0};  ///< over the last second of wall time (step thread)
  /// Set by pause / reset (control thread): the next step starts the factor afresh.
  std::atomic<bool> restart_real_time_factor_{false};

  std::vector<ToolIo> tools_;
  std::unique_ptr<PoseSetSync> sync_;         ///< lockstep with tools only
  std::vector<Eigen::Isometry3d> set_poses_;  ///< X_ST of the set being applied (work vector)
  ros::Time burst_stamp_;                     ///< stamp of the set whose burst is open
  int burst_steps_done_ = 0;                  ///< steps of the open burst done so far
  bool burst_open_ = false;                   ///< a set was taken and its burst is unfinished
  /// Lockstep with tools: sweeps not yet handed to sim_, each with its stamp_end. A sweep ending
  /// at a pose is cut at the first step of a later pose set, whichever of the sweep and that
  /// pose reached the node first, so a replay cuts the same way on a loaded machine.
  /// At most kMaxDeferredSweeps wait (the oldest is dropped, with a warning).
  std::vector<std::pair<ros::Time, core::BladeSweep>> deferred_sweeps_;
  static constexpr std::size_t kMaxDeferredSweeps = 1000;
  ros::NodeHandle nh_;
  ros::WallTimer resume_timer_;  ///< one-shot: resumes lockstep on the main thread after un-pause
  ros::Publisher surface_pub_, tool_marker_pub_, stats_pub_, rigid_node_pub_;
  visualization_msgs::Marker surface_marker_;  ///< tissue/surface, reused between publishes
  std::vector<char> contact_flags_;            ///< per node: touched by a tool (work vector)
  ros::Subscriber blade_sub_;
  ros::ServiceServer reset_srv_, pause_srv_, step_srv_;
  ros::WallTimer timer_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::StaticTransformBroadcaster static_broadcaster_;
  ros::CallbackQueue control_queue_;  ///< tissue/pause and tissue/reset
  /// Serves control_queue_; declared last so it stops first when the node is destroyed.
  ros::AsyncSpinner control_spinner_;
};

}  // namespace surgical_sim::ros_layer
