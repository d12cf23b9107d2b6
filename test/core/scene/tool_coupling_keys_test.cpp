// Scene keys tools[].coupling_stiffness, coupling_damping and max_force: defaults, plumbing,
// validation.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace surgical_sim::core {
namespace {

/// A 4 cm box fixed on its underside with one constraint tool; `extra` is appended to the tool.
std::string sceneWithTool(const std::string& extra) {
  return "name: keys\n"
         "mesh: {generator: box, size: [0.04, 0.04, 0.02], resolution: [2, 2, 1]}\n"
         "material: {young_modulus: 5.0e3, poisson_ratio: 0.45, density: 1000.0}\n"
         "model: corotational\nintegrator: implicit_euler_linearized\nsolver: cholmod\n"
         "time_step: 0.01\n"
         "fixed:\n  - region: {max: [.inf, .inf, 1.0e-9]}\n"
         "tools:\n  - {name: tool, radius: 0.0025, shaft_length: 0.03, contact: constraint" +
         extra + "}\n";
}

std::string rejection(const std::string& extra) {
  try {
    parseRuntimeScene(sceneWithTool(extra), "keys.yaml");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

TEST(ToolCouplingKeys, DefaultsAndExplicitValues) {
  const RuntimeScene defaults = parseRuntimeScene(sceneWithTool(""), "keys.yaml");
  ASSERT_EQ(defaults.tools.size(), 1u);
  EXPECT_EQ(defaults.tools[0].coupling_stiffness, 1e4);
  EXPECT_EQ(defaults.tools[0].max_force, 20.0);
  EXPECT_EQ(defaults.tools[0].coupling_damping, 0.0);
  const RuntimeScene set = parseRuntimeScene(
      sceneWithTool(", coupling_stiffness: 2.5e3, coupling_damping: 40.0, max_force: 3.0"),
      "keys.yaml");
  EXPECT_EQ(set.tools[0].coupling_stiffness, 2.5e3);
  EXPECT_EQ(set.tools[0].coupling_damping, 40.0);
  EXPECT_EQ(set.tools[0].max_force, 3.0);
}

TEST(ToolCouplingKeys, OutOfRangeValuesAreRejectedNamingTheKey) {
  for (const char* bad : {"0.0", "-1.0", "1.0e8", ".nan"}) {
    const std::string message = rejection(std::string(", coupling_stiffness: ") + bad);
    EXPECT_NE(message.find("key 'tools[0].coupling_stiffness'"), std::string::npos) << message;
  }
  for (const char* bad : {"-1.0", "1.0e6", ".nan"}) {
    const std::string message = rejection(std::string(", coupling_damping: ") + bad);
    EXPECT_NE(message.find("key 'tools[0].coupling_damping'"), std::string::npos) << message;
  }
  for (const char* bad : {"0.0", "-5.0", "1.0e5", ".inf"}) {
    const std::string message = rejection(std::string(", max_force: ") + bad);
    EXPECT_NE(message.find("key 'tools[0].max_force'"), std::string::npos) << message;
  }
}

TEST(ToolCouplingKeys, MaxForceReachesTheSimulation) {
  // A tool 8 mm into the fixed underside from below: k_c d = 80 N, capped at max_force = 3 N.
  RuntimeScene scene = parseRuntimeScene(sceneWithTool(", max_force: 3.0"), "keys.yaml");
  scene.gravity.setZero();
  TissueSimulation sim(scene);
  Eigen::Isometry3d X_ST = Eigen::Isometry3d::Identity();  // pointing up (z_T = z_S)
  X_ST.translation() = Eigen::Vector3d(0.02, 0.02, 0.0055);
  sim.setToolPose(0, X_ST);
  const SimulationStepStats s = sim.step();
  EXPECT_EQ(s.report.status, StepStatus::ContactLimited) << toString(s.report.status);
  EXPECT_NEAR(sim.toolContact(0).f0_S.norm(), 3.0, 1e-9);
  EXPECT_STREQ(toString(StepStatus::ContactLimited), "contact_limited");
}

}  // namespace
}  // namespace surgical_sim::core
