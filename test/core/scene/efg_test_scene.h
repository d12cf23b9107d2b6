#pragma once
// A small efg benchmark scene (beam cantilever, quasi-static, two resolutions) and a text
// substitution for deriving variants of it; shared by the scene-key and benchmark-case tests.

#include <gtest/gtest.h>

#include <string>

namespace surgical_sim::test {

/// Benchmark scene text: 0.1 x 0.02 x 0.02 m efg beam under gravity, tip displacement against
/// Euler-Bernoulli + Timoshenko, efg spacing 2.5 mm, 8 neighbours, polar rotation.
inline const char* kEfgBench = R"(
name: efg_unit
mesh:
  generator: beam
  size: [0.1, 0.02, 0.02]
  resolutions: [[10, 2, 2], [20, 4, 4]]
material:
  young_modulus: 1.0e6
  poisson_ratio: 0.3
  density: 1000.0
models: [efg]
integrators: quasi_static
solvers: cholmod
time_step: 1.0
steps: 1
gravity: [0.0, 0.0, -9.81]
fixed:
  - region: {max: [1.0e-9, .inf, .inf]}
measure:
  type: tip_displacement
  region: {min: [0.099999999, -.inf, -.inf]}
  component: z
  reference_formula: euler_bernoulli_timoshenko
efg:
  spacing: 0.0025
  neighbours: 8
  kernel_support: 3.0
  volume_samples: 4
  rotation: polar
)";

/// `text` with the first `from` replaced by `to` (a test failure when `from` is absent).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return text.replace(pos, from.size(), to);
}

}  // namespace surgical_sim::test
