#pragma once

#include <ros/time.h>

#include <Eigen/Geometry>
#include <vector>

namespace surgical_sim::ros_layer {

/// Groups the tool poses of a lockstep simulation into synchronized sets: a set is complete when
/// every tool holds a waiting pose whose header stamp is newer than the last taken set. Each tool
/// keeps only its newest waiting pose. No ROS communication (usable without roscore); O(tools)
/// per call, no allocation after construction except in neverPosed().
class PoseSetSync {
 public:
  /// What offer() did with a pose.
  enum class Offer {
    Accepted,  ///< the tool's waiting pose for the next set
    Replaced,  ///< replaced the tool's newer-than-last-set waiting pose (a pose was dropped)
    Stale,     ///< ignored: stamp not newer than the last set or the tool's waiting pose
  };

  /// @throws std::invalid_argument if num_tools < 1.
  explicit PoseSetSync(int num_tools);

  /// Offers tool `tool`'s (0 <= tool < numTools()) tip pose X_ST stamped `stamp`.
  Offer offer(int tool, const ros::Time& stamp, const Eigen::Isometry3d& X_ST);
  /// True when every tool has a waiting pose (all newer than the last taken set).
  bool complete() const;
  /// Takes the complete set (precondition: complete()): X_ST[i] = tool i's waiting pose; returns
  /// the set's stamp, the newest stamp of its poses, which becomes the last set stamp.
  ros::Time take(std::vector<Eigen::Isometry3d>& X_ST);
  /// Tools (ascending) that never had a pose accepted since construction or reset(): they block
  /// every set.
  std::vector<int> neverPosed() const;
  /// Stamp of the last taken set (zero before the first).
  const ros::Time& lastSetStamp() const { return last_set_; }
  int numTools() const { return static_cast<int>(waiting_.size()); }
  /// Forgets the waiting poses, the last set stamp and which tools were ever posed.
  void reset();

 private:
  struct Waiting {
    bool valid = false;  ///< holds a pose newer than last_set_
    bool ever = false;   ///< had a pose accepted since reset
    ros::Time stamp;
    Eigen::Isometry3d X_ST = Eigen::Isometry3d::Identity();
  };
  std::vector<Waiting> waiting_;
  ros::Time last_set_;
};

}  // namespace surgical_sim::ros_layer
