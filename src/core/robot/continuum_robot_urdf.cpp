#include "surgical_sim/core/robot/continuum_robot_urdf.h"

#include <sstream>

#include "surgical_sim/core/common/number_text.h"

namespace surgical_sim::core {
namespace {

/// A cylinder along x centred at x = centre [m], as a <visual> element.
std::string cylinderAlongX(double centre, double radius, double length,
                           const std::string& material) {
  return "    <visual>\n      <origin xyz=\"" + numberText(centre) +
         " 0 0\" rpy=\"0 1.5707963267948966 0\"/>\n      <geometry><cylinder radius=\"" +
         numberText(radius) + "\" length=\"" + numberText(length) +
         "\"/></geometry>\n      <material name=\"" + material + "\"/>\n    </visual>\n";
}

std::string floatingJoint(const std::string& parent, const std::string& child, double x) {
  return "  <joint name=\"" + child + "_joint\" type=\"floating\">\n    <parent link=\"" + parent +
         "\"/>\n    <child link=\"" + child + "\"/>\n    <origin xyz=\"" + numberText(x) +
         " 0 0\" rpy=\"0 0 0\"/>\n  </joint>\n";
}

}  // namespace

std::string continuumRobotUrdf(const ContinuumRobotDescription& d,
                               const ContinuumRobotFrames& frames) {
  validateContinuumRobotDescription(d);
  const double t = d.vertebra_thickness;
  const double s = d.vertebra_spacing;
  const auto disc = [&](double x) {
    return t > 0.0 ? cylinderAlongX(0.0, d.outerRadiusAt(x), t, "vertebra") : std::string();
  };
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n"
      << "<!-- Continuum robot '" << d.name
      << "', generated from its description (core::continuumRobotUrdf). -->\n"
      << "<robot name=\"continuum_robot_" << d.name << "\">\n"
      << "  <material name=\"vertebra\"><color rgba=\"0.75 0.75 0.8 1\"/></material>\n"
      << "  <material name=\"soft_section\"><color rgba=\"0.9 0.55 0.3 0.5\"/></material>\n"
      << "  <link name=\"" << frames.base << "\">\n"
      << disc(0.0) << "  </link>\n";
  for (int k = 1; k <= d.num_vertebrae; ++k) {
    const double x = k * s;
    out << "  <link name=\"" << frames.rigidNode(k) << "\">\n"
        << disc(x) << cylinderAlongX(-0.5 * s, d.outerRadiusAt(x - 0.5 * s), s - t, "soft_section")
        << "  </link>\n"
        << floatingJoint(frames.base, frames.rigidNode(k), x);
  }
  out << "  <link name=\"" << frames.tip << "\"/>\n"
      << floatingJoint(frames.rigidNode(d.num_vertebrae), frames.tip, 0.0) << "</robot>\n";
  return out.str();
}

}  // namespace surgical_sim::core
