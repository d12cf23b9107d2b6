// Scene keys tools[].coupling_stiffness, coupling_damping, max_force and contact.full_delassus:
// defaults, plumbing, validation.
#include <gtest/gtest.h>

#include <cmath>
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

TEST(ContactSolverKeys, FullDelassusIsTrueOrFalseAndDefaultsToFalse) {
  EXPECT_FALSE(parseRuntimeScene(sceneWithTool(""), "keys.yaml").contact_full_delassus);
  for (const std::string value : {"true", "false"}) {
    const RuntimeScene scene = parseRuntimeScene(
        sceneWithTool("") + "contact: {full_delassus: " + value + "}\n", "keys.yaml");
    EXPECT_EQ(scene.contact_full_delassus, value == "true");
  }
  for (const std::string bad : {"1", "yes", "[true]", "''"}) {
    try {
      parseRuntimeScene(sceneWithTool("") + "contact: {full_delassus: " + bad + "}\n", "keys.yaml");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("key 'contact.full_delassus'"), std::string::npos) << message;
    }
  }
  try {
    parseRuntimeScene(sceneWithTool("") + "contact: {full_delasus: true}\n", "keys.yaml");
    ADD_FAILURE() << "accepted a misspelt key";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("key 'contact.full_delasus': unknown key"), std::string::npos)
        << message;
  }
}

TEST(ContactSolverKeys, FullDelassusSolvesEveryColumnForTheSameForce) {
  Eigen::Vector3d force[2];
  long solves[2] = {0, 0};
  for (int full = 0; full < 2; ++full) {
    RuntimeScene scene = parseRuntimeScene(
        sceneWithTool("") + "contact: {full_delassus: " + (full ? "true" : "false") + "}\n",
        "keys.yaml");
    scene.gravity.setZero();
    TissueSimulation sim(scene);
    Eigen::Isometry3d X_ST = Eigen::Isometry3d::Identity();  // pointing down onto the top face
    X_ST.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    X_ST.translation() = Eigen::Vector3d(0.02, 0.02, 0.02 + 0.0025 - 0.001);
    sim.setToolPose(0, X_ST);
    for (int k = 0; k < 3; ++k) {
      const SimulationStepStats s = sim.step();
      ASSERT_EQ(s.report.status, StepStatus::Ok) << toString(s.report.status);
      solves[full] += s.contact_timings.compliance_solves;
    }
    force[full] = sim.toolContact(0).f0_S;
  }
  EXPECT_GT(force[0].z(), 0.0);
  EXPECT_LT((force[1] - force[0]).norm(), 1e-6 * force[0].norm());
  EXPECT_GT(solves[1], solves[0]);  // every column and the correction
}

}  // namespace
}  // namespace surgical_sim::core
