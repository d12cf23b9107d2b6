#include "surgical_sim/ros/tissue_simulator_node.h"

#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/Marker.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "surgical_sim/ContactModel.h"
#include "surgical_sim/TissueStats.h"
#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/ros/conversions.h"
#include "surgical_sim/ros/parameters.h"

namespace surgical_sim::ros_layer {

TissueSimulatorNode::TissueSimulatorNode(ros::NodeHandle& nh, ros::NodeHandle& pnh)
    : nh_(nh), tf_listener_(tf_buffer_), control_spinner_(1, &control_queue_) {
  const std::string scene_path = requiredStringParam(pnh, "scene", "path of a scene YAML file");
  realtime_ = boolParam(pnh, "realtime", true);
  steps_per_pose_ = intParam(pnh, "steps_per_pose", 1, 1, 1000, "");
  world_frame_ = stringParam(pnh, "world_frame", "world");
  tissue_frame_ = stringParam(pnh, "tissue_frame", "tissue");
  max_tool_distance_ = numberParam(pnh, "max_tool_distance", 5.0, {0.0, 1000.0, true}, "m");
  surface_period_ = 1.0 / numberParam(pnh, "surface_rate", 30.0, {0.0, 1000.0, true}, "Hz");
  force_arrow_scale_ = numberParam(pnh, "force_arrow_scale", 0.03, {0.0, 10.0, true}, "m/N");

  const core::RuntimeScene loaded = core::loadRuntimeScene(scene_path);
  if (!loaded.bodies.empty()) {
    multi_ = std::make_unique<core::MultiBodySimulation>(loaded);
  } else {
    sim_ = std::make_unique<core::TissueSimulation>(loaded);
    for (const std::string& warning : sim_->warnings())
      ROS_WARN_NAMED("tissue_simulator", "scene %s: %s", scene_path.c_str(), warning.c_str());
  }
  X_WS_ = scene().tissue_pose;

  geometry_msgs::TransformStamped t = tf2::eigenToTransform(X_WS_);
  t.header.stamp = ros::Time::now();
  t.header.frame_id = world_frame_;
  t.child_frame_id = tissue_frame_;
  static_broadcaster_.sendTransform(t);

  surface_pub_ = nh.advertise<visualization_msgs::Marker>("tissue/surface", 2, true);
  tool_marker_pub_ = nh.advertise<visualization_msgs::Marker>("tissue/tools", 10);
  stats_pub_ = nh.advertise<surgical_sim::TissueStats>("tissue/stats", 100);
  if (multi_)
    rigid_node_pub_ = nh.advertise<visualization_msgs::Marker>("tissue/rigid_nodes", 2, true);
  tools_.resize(static_cast<std::size_t>(numTools()));
  for (int i = 0; i < numTools(); ++i) {
    const core::ToolSpec& spec = scene().tools[static_cast<std::size_t>(i)];
    ToolIo& io = tools_[static_cast<std::size_t>(i)];
    io.pose_sub = nh.subscribe<geometry_msgs::PoseStamped>(
        spec.pose_topic, 1000, [this, i](const auto& msg) { onPose(msg, i); });
    if (spec.grasp && !spec.grasp->topic.empty())
      io.grasp_sub = nh.subscribe<std_msgs::Bool>(spec.grasp->topic, 100,
                                                  [this, i](const auto& msg) { onGrasp(msg, i); });
    if (spec.grasp && !spec.grasp->joint.empty())
      io.grip_sub = nh.subscribe<sensor_msgs::JointState>(
          spec.grasp->joint_topic, 100, [this, i](const auto& msg) { onGrip(msg, i); });
    if (!spec.contact) continue;  // a tool without contact publishes nothing
    io.wrench_pub = nh.advertise<geometry_msgs::WrenchStamped>(spec.wrench_topic, 1000);
    io.contact_pub = nh.advertise<surgical_sim::ContactModel>(spec.contact_model_topic, 1000);
  }
  // pause and reset are served by their own thread: they answer (and interrupt) during a long
  // tissue/step or lockstep burst, which runs on the main thread.
  ros::NodeHandle control_nh(nh);
  control_nh.setCallbackQueue(&control_queue_);
  reset_srv_ = control_nh.advertiseService("tissue/reset", &TissueSimulatorNode::onReset, this);
  pause_srv_ = control_nh.advertiseService("tissue/pause", &TissueSimulatorNode::onPause, this);
  step_srv_ = nh.advertiseService("tissue/step", &TissueSimulatorNode::onStep, this);
  blade_sub_ = nh.subscribe("cutting/blade_sweep", 100, &TissueSimulatorNode::onBladeSweep, this);

  // Realtime: wall-clock paced at dt. Lockstep with tools: driven by pose sets. Lockstep without
  // tools: free-running as fast as possible.
  if (!realtime_ && numTools() > 0) sync_ = std::make_unique<PoseSetSync>(numTools());
  if (realtime_ || numTools() == 0) {
    const double period = realtime_ ? scene().time_step : 1e-6;
    timer_ = nh.createWallTimer(ros::WallDuration(period), [this](const auto&) { onTimer(); });
  }
  if (multi_) {
    ROS_INFO_NAMED("tissue_simulator",
                   "scene '%s': %d bodies, %d connective layer(s), %d unknowns, %s mode, %d "
                   "tool(s), components:",
                   scene().name.c_str(), multi_->numBodies(), multi_->numLayers(),
                   multi_->coupling().numUnknowns(), realtime_ ? "realtime" : "lockstep",
                   numTools());
  } else {
    ROS_INFO_NAMED("tissue_simulator",
                   "scene '%s': %d nodes, %d elements, model %s, %s mode, %d tool(s), components:",
                   scene().name.c_str(), sim_->mesh().numNodes(), sim_->mesh().numElements(),
                   sim_->model().name().c_str(), realtime_ ? "realtime" : "lockstep", numTools());
  }
  for (const auto& c : multi_ ? multi_->components() : sim_->components())
    ROS_INFO_NAMED("tissue_simulator", "  %s", c.c_str());
  control_spinner_.start();
}

void TissueSimulatorNode::interrupt(const char* reason) {
  interrupt_reason_ = reason;
  ++interrupts_;
}

const char* TissueSimulatorNode::interruption(unsigned since) const {
  if (ros::isShuttingDown()) return "shutdown";
  return interrupts_.load() != since ? interrupt_reason_.load() : nullptr;
}

bool TissueSimulatorNode::toTissueFrame(const geometry_msgs::PoseStamped& msg,
                                        Eigen::Isometry3d& X_ST) {
  if (!acceptPose(msg.pose, max_tool_distance_, "tissue_simulator")) return false;
  Eigen::Isometry3d X_SF;
  if (!frameInTissue(msg.header.frame_id, "tool pose", X_SF)) return false;
  X_ST = X_SF * toEigen(msg.pose);
  return true;
}

bool TissueSimulatorNode::frameInTissue(const std::string& frame, const char* what,
                                        Eigen::Isometry3d& X_SF) {
  if (frame == tissue_frame_) {
    X_SF = Eigen::Isometry3d::Identity();
  } else if (frame == world_frame_ || frame.empty()) {
    X_SF = X_WS_.inverse();
  } else {
    try {
      X_SF = tf2::transformToEigen(tf_buffer_.lookupTransform(tissue_frame_, frame, ros::Time(0)));
    } catch (const tf2::TransformException& e) {
      ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator", "rejected %s in unknown frame '%s': %s",
                              what, frame.c_str(), e.what());
      return false;
    }
  }
  return true;
}

void TissueSimulatorNode::onPose(const geometry_msgs::PoseStamped::ConstPtr& msg, int tool) {
  Eigen::Isometry3d X_ST;
  if (!toTissueFrame(*msg, X_ST)) return;
  if (!sync_) {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    setToolPose(tool, X_ST);
    tools_[static_cast<std::size_t>(tool)].has_pose = true;
    tools_[static_cast<std::size_t>(tool)].X_ST = X_ST;
    return;
  }
  {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    offerPose(tool, msg->header.stamp.isZero() ? ros::Time::now() : msg->header.stamp, X_ST);
  }
  runLockstep();
}

void TissueSimulatorNode::offerPose(int tool, const ros::Time& stamp,
                                    const Eigen::Isometry3d& X_ST) {
  const auto name = [this](int i) { return scene().tools[static_cast<std::size_t>(i)].name; };
  const PoseSetSync::Offer offer = sync_->offer(tool, stamp, X_ST);
  if (offer == PoseSetSync::Offer::Stale)
    ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator",
                            "lockstep: tool %s pose stamped %.6f s ignored: not newer than the "
                            "last stepped set (%.6f s) or its waiting pose (tissue/reset "
                            "restarts a replay)",
                            name(tool).c_str(), stamp.toSec(), sync_->lastSetStamp().toSec());
  if (offer != PoseSetSync::Offer::Replaced) return;
  ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator",
                          "lockstep: tool %s overran: its pose stamped %.6f s replaces a waiting "
                          "one before every tool's pose of that set arrived (a dropped pose)",
                          name(tool).c_str(), stamp.toSec());
  std::string blocking;
  for (int i : sync_->neverPosed()) blocking += (blocking.empty() ? "" : ", ") + name(i);
  if (!blocking.empty())
    ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator",
                            "lockstep: no step until every tool has a pose; waiting for the first "
                            "pose of tool(s) %s",
                            blocking.c_str());
}

void TissueSimulatorNode::runLockstep() {
  const unsigned interrupts = interrupts_.load();
  while (!paused_ && !interruption(interrupts)) {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    if (!burst_open_) {
      if (!sync_->complete()) return;
      burst_stamp_ = sync_->take(set_poses_);
      for (int i = 0; i < numTools(); ++i) {
        ToolIo& io = tools_[static_cast<std::size_t>(i)];
        io.X_ST = set_poses_[static_cast<std::size_t>(i)];
        io.has_pose = true;
        setToolPose(i, io.X_ST);
      }
      burst_steps_done_ = 0;
      burst_open_ = true;
    }
    const int k = ++burst_steps_done_;
    if (k == 1) requestDeferredCuts(burst_stamp_);
    const bool ok = stepAndPublish(burst_stamp_, k == steps_per_pose_, burst_stamp_, k);
    if (!ok || k == steps_per_pose_) burst_open_ = false;
  }
}

void TissueSimulatorNode::onGrasp(const std_msgs::Bool::ConstPtr& msg, int tool) {
  std::lock_guard<std::mutex> lock(sim_mutex_);
  setGrasp(tool, msg->data);
}

void TissueSimulatorNode::onGrip(const sensor_msgs::JointState::ConstPtr& msg, int tool) {
  const core::ToolSpec& spec = scene().tools[static_cast<std::size_t>(tool)];
  const core::GraspSpec& grasp = *spec.grasp;
  const auto it = std::find(msg->name.begin(), msg->name.end(), grasp.joint);
  if (it == msg->name.end()) return;  // a JointState of other joints
  const auto k = static_cast<std::size_t>(it - msg->name.begin());
  if (k >= msg->position.size() || !std::isfinite(msg->position[k])) {
    ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator",
                            "tool %s: %s has no finite position for grip joint %s; jaws unchanged",
                            spec.name.c_str(), grasp.joint_topic.c_str(), grasp.joint.c_str());
    return;
  }
  std::lock_guard<std::mutex> lock(sim_mutex_);
  setGrasp(tool, msg->position[k] <= grasp.closed_angle);
}

void TissueSimulatorNode::setToolPose(int tool, const Eigen::Isometry3d& X_ST) {
  if (!multi_) {
    sim_->setToolPose(tool, X_ST);
    return;
  }
  try {
    multi_->setToolPose(tool, X_ST);
  } catch (const std::invalid_argument& e) {
    ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator", "rejected tool pose: %s", e.what());
  }
}

void TissueSimulatorNode::setGrasp(int tool, bool closed) {
  if (multi_) {
    multi_->setGrasp(tool, closed);
  } else {
    sim_->setGrasp(tool, closed);
  }
}

void TissueSimulatorNode::onBladeSweep(const surgical_sim::BladeSweep::ConstPtr& msg) {
  if (multi_) {
    ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator",
                            "rejected cutting/blade_sweep: a multi-body scene cannot be cut");
    return;
  }
  Eigen::Isometry3d X_SF;
  if (!frameInTissue(msg->header.frame_id, "cutting/blade_sweep", X_SF)) return;
  core::BladeSweep sweep;
  sweep.start.resize(3, static_cast<Eigen::Index>(msg->start.size()));
  sweep.end.resize(3, static_cast<Eigen::Index>(msg->end.size()));
  for (std::size_t i = 0; i < msg->start.size(); ++i)
    sweep.start.col(static_cast<Eigen::Index>(i)) = X_SF * toEigen(msg->start[i]);
  for (std::size_t i = 0; i < msg->end.size(); ++i)
    sweep.end.col(static_cast<Eigen::Index>(i)) = X_SF * toEigen(msg->end[i]);
  try {
    std::lock_guard<std::mutex> lock(sim_mutex_);
    if (sync_) {
      core::validateBladeSweep(sweep);
      if (deferred_sweeps_.size() >= kMaxDeferredSweeps) {
        ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator",
                                "dropped a cutting/blade_sweep: %zu sweeps wait for a tool pose "
                                "stamped after them (stamps ahead of the poses?)",
                                deferred_sweeps_.size());
        deferred_sweeps_.erase(deferred_sweeps_.begin());
      }
      deferred_sweeps_.emplace_back(msg->stamp_end, sweep);
    } else {
      sim_->requestCut(sweep);
    }
  } catch (const std::invalid_argument& e) {
    ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator", "rejected cutting/blade_sweep: %s", e.what());
  }
}

void TissueSimulatorNode::requestDeferredCuts(const ros::Time& set_stamp) {
  std::vector<std::pair<ros::Time, core::BladeSweep>> later;
  for (auto& [stamp_end, sweep] : deferred_sweeps_) {
    if (stamp_end >= set_stamp) {
      later.emplace_back(stamp_end, std::move(sweep));
      continue;
    }
    try {
      sim_->requestCut(sweep);
    } catch (const std::invalid_argument& e) {
      ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator", "rejected cutting/blade_sweep: %s",
                              e.what());
    }
  }
  deferred_sweeps_ = std::move(later);
}

void TissueSimulatorNode::onTimer() {
  if (paused_) return;
  const double now = ros::WallTime::now().toSec();
  const bool surface = !realtime_ || now - last_surface_wall_ >= surface_period_;
  if (surface) last_surface_wall_ = now;
  std::lock_guard<std::mutex> lock(sim_mutex_);
  stepAndPublish(ros::Time::now(), surface);
}

bool TissueSimulatorNode::stepAndPublish(const ros::Time& stamp, bool publish_surface,
                                         const ros::Time& set_stamp, int burst_step) {
  const core::SimulationStepStats s = stepSimulation();
  ++step_count_;
  core::Stopwatch publish_watch;
  for (int i = 0; i < numTools(); ++i) publishTool(i, stamp);
  if (publish_surface) {
    publishSurface(stamp);
    publishToolMarkers(stamp);
  }

  surgical_sim::TissueStats stats;
  stats.header.stamp = stamp;
  stats.header.frame_id = tissue_frame_;
  stats.step = step_count_;
  stats.sim_time = simulationTime();
  stats.step_time = s.step_seconds;
  stats.collision_time = s.collision_seconds;
  stats.integrate_time = s.integrate_seconds;
  stats.contact_time = s.contact_seconds;
  stats.cut_time = s.cut_seconds;
  stats.publish_time = last_publish_seconds_;
  stats.newton_iterations = static_cast<unsigned>(s.report.newton_iterations);
  stats.linear_iterations = static_cast<unsigned>(s.report.linear_iterations);
  stats.residual = s.report.residual;
  stats.energy = s.report.energy;
  stats.contacts = static_cast<unsigned>(s.contacts);
  stats.pieces = static_cast<unsigned>(multi_ ? multi_->numBodies() : sim_->numComponents());
  stats.status = core::toString(s.report.status);
  stats.components = multi_ ? multi_->components() : sim_->components();
  if (restart_real_time_factor_.exchange(false)) real_time_factor_.clear();
  stats.real_time_factor = real_time_factor_.add(ros::WallTime::now().toSec(), stats.sim_time);
  // Realtime mode paces steps at dt: a factor below 0.9 (over a full window) means the machine
  // cannot keep up with this scene.
  if (realtime_ && stats.real_time_factor > 0.0 && stats.real_time_factor < 0.9 &&
      stats.sim_time >= 1.0)
    ROS_WARN_THROTTLE_NAMED(5.0, "tissue_simulator",
                            "falling behind real time: real-time factor %.2f (%.0f steps/s "
                            "against the scene's %.0f Hz); a coarser mesh, a larger time step or "
                            "a faster solver would keep up",
                            stats.real_time_factor, stats.real_time_factor / scene().time_step,
                            1.0 / scene().time_step);
  const bool failed = s.report.status == core::StepStatus::SolverFailed ||
                      s.report.status == core::StepStatus::NonFinite ||
                      s.report.status == core::StepStatus::BlowUp;
  stats.pose_set_stamp = set_stamp;
  stats.burst_step = static_cast<unsigned>(burst_step);
  stats.burst_end = burst_step > 0 && (failed || burst_step == steps_per_pose_);
  stats_pub_.publish(stats);
  last_publish_seconds_ = publish_watch.seconds();

  if (failed)
    ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator", "step %u failed: %s (state kept finite)",
                            step_count_, stats.status.c_str());
  if (sim_ && !sim_->cutError().empty())
    ROS_WARN_THROTTLE_NAMED(1.0, "tissue_simulator", "step %u: %s", step_count_,
                            sim_->cutError().c_str());
  return !failed;
}

void TissueSimulatorNode::publishTool(int tool, const ros::Time& stamp) {
  const core::ToolSpec& spec = scene().tools[static_cast<std::size_t>(tool)];
  if (!spec.contact) return;
  const core::ContactLinearization c = toolContact(tool);
  const Eigen::Matrix3d R_WS = X_WS_.linear();
  const Eigen::Vector3d f_W = R_WS * c.f0_S;
  const Eigen::Matrix3d K_W = R_WS * c.K_S * R_WS.transpose();
  ToolIo& io = tools_[static_cast<std::size_t>(tool)];

  geometry_msgs::WrenchStamped wrench;
  wrench.header.stamp = stamp;
  wrench.header.frame_id = world_frame_;
  wrench.wrench.force = toVector3Msg(f_W);
  io.wrench_pub.publish(wrench);

  surgical_sim::ContactModel model;
  model.header = wrench.header;
  model.tool = spec.name;
  model.in_contact = c.in_contact;
  model.point = toPointMsg(X_WS_ * c.p0_S);
  model.force = wrench.wrench.force;
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col) model.stiffness[3 * r + col] = K_W(r, col);
  model.contacts = static_cast<unsigned>(c.contacts);
  io.contact_pub.publish(model);
}

visualization_msgs::Marker& TissueSimulatorNode::surfaceMarker(const ros::Time& stamp) {
  visualization_msgs::Marker& m = surface_marker_;
  m.header.stamp = stamp;
  m.header.frame_id = tissue_frame_;
  m.ns = "tissue";
  m.type = visualization_msgs::Marker::TRIANGLE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.color.a = 1.0;
  return m;
}

void TissueSimulatorNode::publishSurface(const ros::Time& stamp) {
  if (surface_pub_.getNumSubscribers() == 0 && step_count_ > 1) return;
  if (multi_) {
    publishBodies(stamp);
    return;
  }
  const core::SurfaceMesh& surface = sim_->surface();
  const Eigen::VectorXd& x = sim_->surfacePositions();
  // Reused members: no allocation per publish once the surface size is known.
  std::vector<char>& in_contact = contact_flags_;
  in_contact.assign(static_cast<std::size_t>(sim_->mesh().numNodes()), 0);
  for (int n : sim_->contactNodes()) in_contact[static_cast<std::size_t>(n)] = 1;

  visualization_msgs::Marker& m = surfaceMarker(stamp);
  const auto n_tri = static_cast<std::size_t>(surface.triangles.cols());
  m.points.resize(3 * n_tri);
  m.colors.resize(3 * n_tri);
  const Eigen::Matrix3Xd& x0 = sim_->mesh().nodes;
  const std::vector<bool>& cut = sim_->cutFaces();
  for (std::size_t t = 0; t < n_tri; ++t)
    for (int c = 0; c < 3; ++c) {
      const int node = surface.triangles(c, static_cast<Eigen::Index>(t));
      const Eigen::Vector3d p = x.segment<3>(3 * node);
      m.points[3 * t + c] = toPointMsg(p);
      // Tissue pink, darkening with displacement; contact nodes red; cut faces dark red.
      const double d = std::min(1.0, (p - x0.col(node)).norm() / 0.02);
      auto& col = m.colors[3 * t + c];
      col.a = 1.0;
      if (in_contact[static_cast<std::size_t>(node)]) {
        col.r = 1.0f;
        col.g = 0.1f;
        col.b = 0.1f;
      } else if (!cut.empty() && cut[t]) {
        col.r = 0.55f;
        col.g = 0.08f;
        col.b = 0.12f;
      } else {
        col.r = static_cast<float>(0.95 - 0.35 * d);
        col.g = static_cast<float>(0.65 - 0.35 * d);
        col.b = static_cast<float>(0.65 - 0.25 * d);
      }
    }
  surface_pub_.publish(m);
}

void TissueSimulatorNode::publishToolMarkers(const ros::Time& stamp) {
  if (tool_marker_pub_.getNumSubscribers() == 0) return;
  for (int i = 0; i < numTools(); ++i) {
    const ToolIo& io = tools_[static_cast<std::size_t>(i)];
    const core::ToolSpec& spec = scene().tools[static_cast<std::size_t>(i)];
    if (!io.has_pose || !spec.contact) continue;
    visualization_msgs::Marker m;
    m.header.stamp = stamp;
    m.header.frame_id = tissue_frame_;
    m.ns = spec.name;
    m.action = visualization_msgs::Marker::ADD;
    m.color.r = m.color.g = 0.75f;
    m.color.b = 0.8f;
    m.color.a = 1.0f;
    // Tip sphere at the pose; the shaft runs along the tool's -z (the tool z axis points in).
    m.id = 0;
    m.type = visualization_msgs::Marker::SPHERE;
    m.pose = toPoseMsg(io.X_ST);
    m.scale.x = m.scale.y = m.scale.z = 2.0 * spec.radius;
    tool_marker_pub_.publish(m);
    m.id = 1;
    m.type = visualization_msgs::Marker::CYLINDER;
    m.pose = toPoseMsg(io.X_ST * Eigen::Translation3d(0.0, 0.0, -0.5 * spec.shaft_length));
    m.scale.z = spec.shaft_length;
    tool_marker_pub_.publish(m);
    // Force of the tissue on the tool: an arrow from the tip, deleted out of contact.
    const core::ContactLinearization c = toolContact(i);
    m.id = 2;
    m.type = visualization_msgs::Marker::ARROW;
    m.action = c.in_contact ? visualization_msgs::Marker::ADD : visualization_msgs::Marker::DELETE;
    m.pose = toPoseMsg(Eigen::Isometry3d::Identity());
    m.points = {toPointMsg(c.p0_S), toPointMsg(c.p0_S + force_arrow_scale_ * c.f0_S)};
    m.scale.x = 0.002;  // shaft diameter [m]
    m.scale.y = 0.005;  // head diameter [m]
    m.scale.z = 0.006;  // head length [m]
    m.color.r = 1.0f;
    m.color.g = 0.78f;
    m.color.b = 0.16f;
    tool_marker_pub_.publish(m);
  }
}

void TissueSimulatorNode::publishBodies(const ros::Time& stamp) {
  visualization_msgs::Marker& m = surfaceMarker(stamp);
  m.points.clear();
  m.colors.clear();
  const auto add = [&m](const Eigen::Vector3d& p, const Eigen::Vector3f& rgb) {
    m.points.push_back(toPointMsg(p));
    std_msgs::ColorRGBA c;
    c.r = rgb.x();
    c.g = rgb.y();
    c.b = rgb.z();
    c.a = 1.0f;
    m.colors.push_back(c);
  };
  // Organs in their colours, nodes a tool touches red; then the layer surfaces.
  const Eigen::Vector3f red(1.0f, 0.1f, 0.1f);
  for (int b = 0; b < multi_->numBodies(); ++b) {
    std::vector<char>& in_contact = contact_flags_;
    in_contact.assign(static_cast<std::size_t>(multi_->bodyMesh(b).numNodes()), 0);
    for (int n : multi_->contactNodes()[static_cast<std::size_t>(b)])
      in_contact[static_cast<std::size_t>(n)] = 1;
    const Eigen::Vector3f& colour = scene().bodies[static_cast<std::size_t>(b)].colour;
    const Eigen::Matrix3Xi& triangles = multi_->bodySurface(b).triangles;
    const Eigen::VectorXd& x = multi_->bodyPositions(b);
    for (Eigen::Index t = 0; t < triangles.cols(); ++t)
      for (int c = 0; c < 3; ++c) {
        const int node = triangles(c, t);
        add(x.segment<3>(3 * node), in_contact[static_cast<std::size_t>(node)] ? red : colour);
      }
  }
  for (int l = 0; l < multi_->numLayers(); ++l) {
    const Eigen::Matrix3Xd x = multi_->layerSurfacePositions(l);
    const Eigen::Matrix3Xi& triangles = multi_->layerSurface(l).triangles;
    for (Eigen::Index t = 0; t < triangles.cols(); ++t)
      for (int c = 0; c < 3; ++c)
        add(x.col(triangles(c, t)), scene().connective[static_cast<std::size_t>(l)].colour);
  }
  surface_pub_.publish(m);

  if (rigid_node_pub_.getNumSubscribers() == 0 && step_count_ > 1) return;
  visualization_msgs::Marker axes;
  axes.header = m.header;
  axes.ns = "rigid_nodes";
  axes.type = visualization_msgs::Marker::LINE_LIST;
  axes.action = visualization_msgs::Marker::ADD;
  axes.pose.orientation.w = 1.0;
  axes.scale.x = 0.0005;                 // line width [m]
  constexpr double kAxisLength = 0.004;  // [m]
  for (const core::RigidNodeConfiguration& q : multi_->state().layer_configurations)
    for (int j = 0; j < q.numNodes(); ++j) {
      const Eigen::Matrix3d R = q.q_TN[static_cast<std::size_t>(j)].toRotationMatrix();
      const Eigen::Vector3d& p = q.p_TN[static_cast<std::size_t>(j)];
      for (int k = 0; k < 3; ++k) {
        std_msgs::ColorRGBA c;
        c.r = k == 0 ? 1.0f : 0.0f;
        c.g = k == 1 ? 1.0f : 0.0f;
        c.b = k == 2 ? 1.0f : 0.0f;
        c.a = 1.0f;
        axes.points.push_back(toPointMsg(p));
        axes.points.push_back(toPointMsg(p + kAxisLength * R.col(k)));
        axes.colors.push_back(c);
        axes.colors.push_back(c);
      }
    }
  rigid_node_pub_.publish(axes);
}

bool TissueSimulatorNode::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  interrupt("reset");
  std::lock_guard<std::mutex> lock(sim_mutex_);  // waits for at most the step in progress
  if (multi_) {
    multi_->reset();
  } else {
    sim_->reset();
  }
  restart_real_time_factor_ = true;
  step_count_ = 0;
  if (sync_) sync_->reset();
  deferred_sweeps_.clear();
  burst_open_ = false;
  ROS_INFO_NAMED("tissue_simulator", "reset to the rest state");
  return true;
}

bool TissueSimulatorNode::onPause(std_srvs::SetBool::Request& req,
                                  std_srvs::SetBool::Response& res) {
  paused_ = req.data;
  interrupt("pause");
  restart_real_time_factor_ = true;  // paused time is not behind real time
  // Lockstep: finish the interrupted burst and any set completed meanwhile, on the main thread.
  if (sync_ && !req.data)
    resume_timer_ = nh_.createWallTimer(
        ros::WallDuration(1e-6), [this](const auto&) { runLockstep(); }, true);
  res.success = true;
  res.message = req.data ? "paused" : "running";
  return true;
}

bool TissueSimulatorNode::onStep(surgical_sim::StepTissue::Request& req,
                                 surgical_sim::StepTissue::Response& res) {
  const unsigned interrupts = interrupts_.load();
  res.steps_done = 0;
  if (!paused_) {
    res.success = false;
    res.message = "tissue/step needs the simulator paused (call tissue/pause with data: true)";
    return true;
  }
  if (req.steps < 1 || req.steps > kMaxStepRequest) {
    res.success = false;
    res.message = "steps = " + std::to_string(req.steps) + " must be in [1, " +
                  std::to_string(kMaxStepRequest) + "]";
    return true;
  }
  res.success = false;
  for (unsigned k = 0; k < req.steps; ++k) {
    if (const char* reason = interruption(interrupts)) {
      res.message = std::string("interrupted by ") + reason + " after " +
                    std::to_string(res.steps_done) + " steps";
      return true;
    }
    std::lock_guard<std::mutex> lock(sim_mutex_);
    if (!stepAndPublish(ros::Time::now(), k + 1 == req.steps)) {
      res.message = "step failed after " + std::to_string(res.steps_done) + " steps";
      return true;
    }
    ++res.steps_done;
  }
  res.success = true;
  res.message = "advanced " + std::to_string(res.steps_done) + " steps";
  return true;
}

}  // namespace surgical_sim::ros_layer
