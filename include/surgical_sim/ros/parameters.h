#pragma once

#include <ros/ros.h>

#include <stdexcept>
#include <string>

namespace surgical_sim::ros_layer {

/// Private parameter `name` or `fallback` when it is not set.
template <class T>
T param(const ros::NodeHandle& pnh, const std::string& name, const T& fallback) {
  T value = fallback;
  pnh.param(name, value, fallback);
  return value;
}

/// @throws std::invalid_argument(what) unless ok (start-up validation naming the parameter).
inline void requireParam(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace surgical_sim::ros_layer
