#include "surgical_sim/ros/real_time_factor.h"

#include <cmath>
#include <stdexcept>

namespace surgical_sim::ros_layer {

RealTimeFactor::RealTimeFactor(double window_seconds) : window_(window_seconds) {
  if (!(std::isfinite(window_seconds) && window_seconds > 0.0))
    throw std::invalid_argument("RealTimeFactor: window must be finite and > 0 s");
}

double RealTimeFactor::add(double wall_seconds, double sim_time) {
  samples_.emplace_back(wall_seconds, sim_time);
  while (samples_.size() > 2 && wall_seconds - samples_[1].first >= window_) samples_.pop_front();
  const double wall = wall_seconds - samples_.front().first;
  return wall > 0.0 ? (sim_time - samples_.front().second) / wall : 0.0;
}

}  // namespace surgical_sim::ros_layer
