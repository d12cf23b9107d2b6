#pragma once

#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <Eigen/Core>
#include <initializer_list>
#include <string>

namespace surgical_sim::ros_layer {

/// The one strict way every node reads its private parameters.
///
/// A parameter that is not set takes its documented default (checked by the same rule). A
/// parameter that is set with the wrong type is an error, never a silent fallback. Every error is
/// a std::invalid_argument whose message names "~<name>", the unit and the accepted range, e.g.
/// "~rate = 5 Hz is out of range: must be in [100, 20000] Hz" or
/// "~x must be a number in [-10, 10] m, got the string 'far'".
/// The check* functions work on the value as the parameter server holds it (testable without a
/// master); the *Param functions read it from a node handle first.

/// Accepted values of a number parameter: [lo, hi], or (lo, hi] when lo_open. NaN and Inf are
/// never accepted.
struct NumberRange {
  double lo = 0.0;
  double hi = 0.0;
  bool lo_open = false;
};

/// A number (integer or floating point) in `range` [unit].
double checkNumber(const std::string& name, const XmlRpc::XmlRpcValue& value,
                   const NumberRange& range, const std::string& unit);
/// An integer in [lo, hi] [unit] (a floating-point value is a type error).
int checkInt(const std::string& name, const XmlRpc::XmlRpcValue& value, int lo, int hi,
             const std::string& unit);
/// A boolean (true / false; 0 and 1 are type errors).
bool checkBool(const std::string& name, const XmlRpc::XmlRpcValue& value);
/// A string, non-empty unless allow_empty.
std::string checkString(const std::string& name, const XmlRpc::XmlRpcValue& value,
                        bool allow_empty);
/// A string equal to one of `choices`.
std::string checkChoice(const std::string& name, const XmlRpc::XmlRpcValue& value,
                        std::initializer_list<const char*> choices);
/// A list of 3-D points [unit]: either a flat list of numbers x0 y0 z0 x1 y1 z1 ..., or a list
/// of [x, y, z] lists. A string holding such a list in YAML (what `rosrun ... _p:="[[0,0,0]]"`
/// stores) is parsed first. Returns the points as columns (3 x k, k >= 1).
Eigen::Matrix3Xd checkPointList(const std::string& name, const XmlRpc::XmlRpcValue& value,
                                const std::string& unit);

/// Reads ~name (default `fallback`) and checks it with checkNumber.
double numberParam(const ros::NodeHandle& pnh, const std::string& name, double fallback,
                   const NumberRange& range, const std::string& unit);
/// Reads ~name (default `fallback`) and checks it with checkInt.
int intParam(const ros::NodeHandle& pnh, const std::string& name, int fallback, int lo, int hi,
             const std::string& unit);
/// Reads ~name (default `fallback`) and checks it with checkBool.
bool boolParam(const ros::NodeHandle& pnh, const std::string& name, bool fallback);
/// Reads ~name (default `fallback`) and checks it with checkString.
std::string stringParam(const ros::NodeHandle& pnh, const std::string& name,
                        const std::string& fallback, bool allow_empty = false);
/// Reads ~name (default `fallback`) and checks it with checkChoice.
std::string choiceParam(const ros::NodeHandle& pnh, const std::string& name,
                        const std::string& fallback, std::initializer_list<const char*> choices);
/// Reads the required non-empty string ~name; `what` says what it holds.
/// @throws std::invalid_argument "parameter ~name (<what>) is required" when it is not set.
std::string requiredStringParam(const ros::NodeHandle& pnh, const std::string& name,
                                const std::string& what);
/// Reads ~name (default `fallback`, 3 x k) and checks it with checkPointList.
Eigen::Matrix3Xd pointListParam(const ros::NodeHandle& pnh, const std::string& name,
                                const Eigen::Matrix3Xd& fallback, const std::string& unit);

}  // namespace surgical_sim::ros_layer
