#include "surgical_sim/ros/parameters.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace surgical_sim::ros_layer {
namespace {

using XmlRpc::XmlRpcValue;

/// "[lo, hi] unit" or "(lo, hi] unit".
std::string describeRange(const NumberRange& range, const std::string& unit) {
  std::ostringstream s;
  s << (range.lo_open ? "(" : "[") << range.lo << ", " << range.hi << "]"
    << (unit.empty() ? "" : " ") << unit;
  return s.str();
}

/// What a value of the wrong type is, for the message: "the string 'far'", "a list", ...
std::string describeValue(const XmlRpcValue& value) {
  std::ostringstream s;
  switch (value.getType()) {
    case XmlRpcValue::TypeBoolean:
      s << "the boolean " << (static_cast<const bool&>(value) ? "true" : "false");
      break;
    case XmlRpcValue::TypeInt:
      s << "the integer " << static_cast<const int&>(value);
      break;
    case XmlRpcValue::TypeDouble:
      s << "the number " << static_cast<const double&>(value);
      break;
    case XmlRpcValue::TypeString:
      s << "the string '" << static_cast<const std::string&>(value) << "'";
      break;
    case XmlRpcValue::TypeArray:
      s << "a list of " << value.size() << " entries";
      break;
    case XmlRpcValue::TypeStruct:
      s << "a dictionary";
      break;
    default:
      s << "a value of another type";
  }
  return s.str();
}

[[noreturn]] void wrongType(const std::string& name, const std::string& expected,
                            const XmlRpcValue& value) {
  throw std::invalid_argument("~" + name + " must be " + expected + ", got " +
                              describeValue(value));
}

bool isNumber(const XmlRpcValue& value) {
  return value.getType() == XmlRpcValue::TypeInt || value.getType() == XmlRpcValue::TypeDouble;
}

double toDouble(const XmlRpcValue& value) {
  return value.getType() == XmlRpcValue::TypeInt ? static_cast<const int&>(value)
                                                 : static_cast<const double&>(value);
}

/// A parsed YAML node as the parameter server would hold it: sequences become lists, scalars
/// numbers when they read as one, strings otherwise.
XmlRpcValue fromYaml(const YAML::Node& node) {
  if (node.IsSequence()) {
    XmlRpcValue list;
    list.setSize(static_cast<int>(node.size()));
    for (std::size_t i = 0; i < node.size(); ++i) list[static_cast<int>(i)] = fromYaml(node[i]);
    return list;
  }
  if (node.IsScalar()) {
    double number = 0.0;
    if (YAML::convert<double>::decode(node, number)) return XmlRpcValue(number);
    return XmlRpcValue(node.Scalar());
  }
  return XmlRpcValue();
}

/// The parameter ~name, or `fallback` when it is not set.
XmlRpcValue lookup(const ros::NodeHandle& pnh, const std::string& name, XmlRpcValue fallback) {
  XmlRpcValue value;
  return pnh.getParam(name, value) ? value : fallback;
}

}  // namespace

double checkNumber(const std::string& name, const XmlRpcValue& value, const NumberRange& range,
                   const std::string& unit) {
  if (!isNumber(value)) wrongType(name, "a number in " + describeRange(range, unit), value);
  const double v = toDouble(value);
  const bool above_lo = range.lo_open ? v > range.lo : v >= range.lo;
  if (!std::isfinite(v) || !above_lo || v > range.hi) {
    std::ostringstream msg;
    msg << "~" << name << " = " << v << (unit.empty() ? "" : " ") << unit
        << " is out of range: must be in " << describeRange(range, unit);
    throw std::invalid_argument(msg.str());
  }
  return v;
}

int checkInt(const std::string& name, const XmlRpcValue& value, int lo, int hi,
             const std::string& unit) {
  const NumberRange range{static_cast<double>(lo), static_cast<double>(hi)};
  if (value.getType() != XmlRpcValue::TypeInt)
    wrongType(name, "an integer in " + describeRange(range, unit), value);
  return static_cast<int>(checkNumber(name, value, range, unit));
}

bool checkBool(const std::string& name, const XmlRpcValue& value) {
  if (value.getType() != XmlRpcValue::TypeBoolean) wrongType(name, "true or false", value);
  return static_cast<const bool&>(value);
}

std::string checkString(const std::string& name, const XmlRpcValue& value, bool allow_empty) {
  const std::string expected = allow_empty ? "a string" : "a non-empty string";
  if (value.getType() != XmlRpcValue::TypeString) wrongType(name, expected, value);
  const std::string& s = value;
  if (s.empty() && !allow_empty) wrongType(name, expected, value);
  return s;
}

std::string checkChoice(const std::string& name, const XmlRpcValue& value,
                        std::initializer_list<const char*> choices) {
  std::string expected;
  for (const char* c : choices)
    expected += (expected.empty() ? "one of '" : ", '") + std::string(c) + "'";
  if (value.getType() != XmlRpcValue::TypeString) wrongType(name, expected, value);
  const std::string& s = value;
  for (const char* c : choices)
    if (s == c) return s;
  wrongType(name, expected, value);
}

Eigen::Matrix3Xd checkPointList(const std::string& name, const XmlRpcValue& value,
                                const std::string& unit) {
  const std::string expected =
      "a list of points [" + unit + "]: x0 y0 z0 x1 y1 z1 ... or [[x0, y0, z0], [x1, y1, z1], ...]";
  if (value.getType() == XmlRpcValue::TypeString) {
    YAML::Node parsed;
    try {
      parsed = YAML::Load(static_cast<const std::string&>(value));
    } catch (const YAML::Exception&) {
      wrongType(name, expected, value);
    }
    if (!parsed.IsSequence()) wrongType(name, expected, value);
    return checkPointList(name, fromYaml(parsed), unit);
  }
  if (value.getType() != XmlRpcValue::TypeArray || value.size() == 0)
    wrongType(name, expected, value);
  const bool nested = value[0].getType() == XmlRpcValue::TypeArray;
  const int points = nested ? value.size() : value.size() / 3;
  if (!nested && value.size() % 3 != 0)
    throw std::invalid_argument("~" + name + " has " + std::to_string(value.size()) +
                                " numbers; expected x y z per point");
  Eigen::Matrix3Xd p(3, points);
  for (int i = 0; i < points; ++i) {
    if (nested && (value[i].getType() != XmlRpcValue::TypeArray || value[i].size() != 3))
      throw std::invalid_argument("~" + name + " point " + std::to_string(i) + " is " +
                                  describeValue(value[i]) + "; expected [x, y, z]");
    for (int c = 0; c < 3; ++c) {
      const XmlRpcValue& coordinate = nested ? value[i][c] : value[3 * i + c];
      if (!isNumber(coordinate))
        throw std::invalid_argument("~" + name + " point " + std::to_string(i) + " has " +
                                    describeValue(coordinate) + "; coordinates are numbers [" +
                                    unit + "]");
      p(c, i) = toDouble(coordinate);
    }
  }
  return p;
}

double numberParam(const ros::NodeHandle& pnh, const std::string& name, double fallback,
                   const NumberRange& range, const std::string& unit) {
  return checkNumber(name, lookup(pnh, name, XmlRpcValue(fallback)), range, unit);
}

int intParam(const ros::NodeHandle& pnh, const std::string& name, int fallback, int lo, int hi,
             const std::string& unit) {
  return checkInt(name, lookup(pnh, name, XmlRpcValue(fallback)), lo, hi, unit);
}

bool boolParam(const ros::NodeHandle& pnh, const std::string& name, bool fallback) {
  return checkBool(name, lookup(pnh, name, XmlRpcValue(fallback)));
}

std::string stringParam(const ros::NodeHandle& pnh, const std::string& name,
                        const std::string& fallback, bool allow_empty) {
  return checkString(name, lookup(pnh, name, XmlRpcValue(fallback)), allow_empty);
}

std::string choiceParam(const ros::NodeHandle& pnh, const std::string& name,
                        const std::string& fallback, std::initializer_list<const char*> choices) {
  return checkChoice(name, lookup(pnh, name, XmlRpcValue(fallback)), choices);
}

std::string requiredStringParam(const ros::NodeHandle& pnh, const std::string& name,
                                const std::string& what) {
  XmlRpcValue value;
  if (!pnh.getParam(name, value))
    throw std::invalid_argument("parameter ~" + name + " (" + what + ") is required");
  return checkString(name, value, false);
}

Eigen::Matrix3Xd pointListParam(const ros::NodeHandle& pnh, const std::string& name,
                                const Eigen::Matrix3Xd& fallback, const std::string& unit) {
  XmlRpcValue value;
  return pnh.getParam(name, value) ? checkPointList(name, value, unit) : fallback;
}

}  // namespace surgical_sim::ros_layer
