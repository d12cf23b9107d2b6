#pragma once

#include <cmath>

#include "surgical_sim/core/robot/continuum_robot_description.h"

namespace surgical_sim::core::test {

/// Small cable robot (fast tests): n vertebrae, 20 mm spacing, tube 12 -> 10 mm, 1 MPa.
inline ContinuumRobotDescription smallCableRobot(int n = 4, int cables = 4) {
  ContinuumRobotDescription d;
  d.name = "small";
  d.num_vertebrae = n;
  d.vertebra_spacing = 0.02;
  d.vertebra_thickness = 0.004;
  d.outer_radius_base = 0.006;
  d.outer_radius_tip = 0.005;
  d.inner_radius = 0.002;
  d.material = Material::create(1e6, 0.45, 1100.0);
  d.vertebra_mass = 0.001;
  d.gravity_enabled = false;
  d.mesh = {1, 8, 2};
  for (int c = 0; c < cables; ++c)
    d.cables.push_back({"c" + std::to_string(c), n, c * M_PI / 2.0, 0.004, 2.0});
  return d;
}

/// Same robot with one pressure chamber per gap range.
inline ContinuumRobotDescription smallPressureRobot() {
  ContinuumRobotDescription d = smallCableRobot(4, 0);
  d.chambers.push_back({"p0", 0, 3, 0.0, 0.0035, 0.001, 0.0, 2e5});
  d.chambers.push_back({"p1", 0, 1, 2.0, 0.0035, 0.001, -1e5, 2e5});
  return d;
}

}  // namespace surgical_sim::core::test
