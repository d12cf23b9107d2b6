#include "surgical_sim/ros/pose_set_sync.h"

#include <stdexcept>
#include <string>

namespace surgical_sim::ros_layer {

PoseSetSync::PoseSetSync(int num_tools) {
  if (num_tools < 1)
    throw std::invalid_argument("PoseSetSync: num_tools = " + std::to_string(num_tools) +
                                " must be >= 1");
  waiting_.resize(static_cast<std::size_t>(num_tools));
}

PoseSetSync::Offer PoseSetSync::offer(int tool, const ros::Time& stamp,
                                      const Eigen::Isometry3d& X_ST) {
  Waiting& w = waiting_.at(static_cast<std::size_t>(tool));
  if (stamp <= last_set_ || (w.valid && stamp <= w.stamp)) return Offer::Stale;
  const Offer result = w.valid ? Offer::Replaced : Offer::Accepted;
  w.valid = true;
  w.ever = true;
  w.stamp = stamp;
  w.X_ST = X_ST;
  return result;
}

bool PoseSetSync::complete() const {
  for (const Waiting& w : waiting_)
    if (!w.valid) return false;
  return true;
}

ros::Time PoseSetSync::take(std::vector<Eigen::Isometry3d>& X_ST) {
  X_ST.resize(waiting_.size());
  ros::Time newest;
  for (std::size_t i = 0; i < waiting_.size(); ++i) {
    X_ST[i] = waiting_[i].X_ST;
    if (waiting_[i].stamp > newest) newest = waiting_[i].stamp;
    waiting_[i].valid = false;
  }
  last_set_ = newest;
  return newest;
}

std::vector<int> PoseSetSync::neverPosed() const {
  std::vector<int> tools;
  for (std::size_t i = 0; i < waiting_.size(); ++i)
    if (!waiting_[i].ever) tools.push_back(static_cast<int>(i));
  return tools;
}

void PoseSetSync::reset() {
  for (Waiting& w : waiting_) w = Waiting{};
  last_set_ = ros::Time();
}

}  // namespace surgical_sim::ros_layer
