// Runtime scenes (loadRuntimeScene): one simulation with its instruments. Every key the runtime
// scene adds has a negative test; benchmark keys are rejected with what to use instead.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace surgical_sim::core {
namespace {

const char* kScene = R"(
name: unit
mesh: {generator: box, size: [0.05, 0.05, 0.05], resolution: [1, 1, 1]}
material: {young_modulus: 20.0e3, poisson_ratio: 0.3, density: 1000.0}
model: svk
integrator: quasi_static
solver: cholmod
time_step: 0.01
fixed:
  - region: {max: [.inf, .inf, 1.0e-9]}
    components: [z]
)";

/// kScene with two tools (a grasper, a scalpel without contact), two trocars and a blade.
std::string instrumentScene() {
  return std::string(kScene) + R"(tools:
  - {name: grasper, radius: 0.0025, shaft_length: 0.05, contact: constraint, grasp: {radius: 0.006}}
  - {name: probe, radius: 0.0025, shaft_length: 0.05, contact: proxy, proxy_stiffness: 200.0}
  - {name: scalpel, contact: none}
trocars:
  - {name: trocar_0, tool: grasper, fulcrum: {position: [-0.05, 0.0, 0.2], rpy: [3.14159, 0, 0]}}
  - {name: trocar_1, tool: probe, fulcrum: {position: [0.05, 0.0, 0.2]}}
blades:
  - {tool: scalpel, edge: [[0, 0, 0], [0, 0, -0.07]]}
robot: {description: trunk, base_pose: {position: [0.3, 0, 0.1]}}
)";
}

std::string rejection(const std::string& yaml) {
  try {
    parseRuntimeScene(yaml, "run.yaml");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return text.replace(pos, from.size(), to);
}

void expectRejected(const std::string& yaml, const std::vector<std::string>& fragments) {
  const std::string message = rejection(yaml);
  for (const auto& f : fragments) EXPECT_NE(message.find(f), std::string::npos) << message;
}

TEST(RuntimeScene, ParsesChoicesIntoEnums) {
  const RuntimeScene s = parseRuntimeScene(kScene, "run.yaml");
  EXPECT_EQ(s.model, ModelKind::Svk);
  EXPECT_EQ(s.integrator, IntegratorKind::QuasiStatic);
  EXPECT_EQ(s.solver, SolverKind::Cholmod);
  EXPECT_EQ(s.resolution, Eigen::Vector3i(1, 1, 1));
  EXPECT_EQ(s.element_type, ElementType::Tet4);
  EXPECT_TRUE(s.tools.empty());
  EXPECT_TRUE(s.trocars.empty());
  EXPECT_FALSE(s.robot.has_value());
}

TEST(RuntimeScene, BenchmarkKeysAreRejectedWithWhatToUseInstead) {
  expectRejected(replaced(kScene, "model: svk", "models: [svk, corotational]"),
                 {"key 'models'", "use 'model: <name>'", "benchmark files"});
  expectRejected(replaced(kScene, "solver: cholmod", "solvers: cholmod"),
                 {"key 'solvers'", "use 'solver: <name>'"});
  expectRejected(replaced(kScene, "integrator: quasi_static", "integrators: [quasi_static]"),
                 {"key 'integrators'"});
  expectRejected(std::string(kScene) + "steps: 10\n", {"key 'steps'", "runs until it is stopped"});
  expectRejected(std::string(kScene) + "measure: {type: self_reference}\n",
                 {"key 'measure'", "measures nothing"});
  expectRejected(std::string(kScene) + "load_factors: [1.0]\n", {"key 'load_factors'"});
  expectRejected(replaced(kScene, "resolution: [1, 1, 1]", "resolutions: [[1, 1, 1], [2, 2, 2]]"),
                 {"key 'mesh.resolutions'", "use 'resolution: [nx, ny, nz]'"});
  expectRejected(replaced(kScene, "resolution: [1, 1, 1]",
                          "resolution: [1, 1, 1], "
                          "element_types: [tet4, tet10]"),
                 {"key 'mesh.element_types'", "use 'element_type: tet4|tet10'"});
}

TEST(RuntimeScene, ABenchmarkFileIsRejectedAsARuntimeSceneAndViceVersa) {
  const std::string t1 =
      std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/bench/t1_steel_cantilever.yaml";
  EXPECT_THROW(loadRuntimeScene(t1), std::invalid_argument);
  EXPECT_NO_THROW(loadBenchmarkScene(t1));
  const std::string palpation =
      std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/scenes/palpation.yaml";
  EXPECT_NO_THROW(loadRuntimeScene(palpation));
  try {
    loadBenchmarkScene(palpation);
    FAIL() << "a runtime scene was accepted as a benchmark";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("key 'model'"), std::string::npos) << e.what();
  }
  expectRejected(replaced(kScene, "model: svk", "model: jelly"), {"key 'model'", "'jelly'"});
  expectRejected(replaced(kScene, "solver: cholmod", "solver: lu"), {"key 'solver'", "'lu'"});
}

TEST(RuntimeScene, MissingOrBadResolutionIsNamed) {
  expectRejected(replaced(kScene, ", resolution: [1, 1, 1]", ""),
                 {"key 'mesh.resolution'", "missing required key"});
  expectRejected(replaced(kScene, "resolution: [1, 1, 1]", "resolution: [0, 1, 1]"),
                 {"key 'mesh.resolution'"});
  expectRejected(replaced(kScene, "resolution: [1, 1, 1]", "resolution: [4096, 4096, 4096]"),
                 {"key 'mesh.resolution'", "needs about"});
  expectRejected(
      replaced(kScene, "resolution: [1, 1, 1]", "resolution: [1, 1, 1], element_type: tet7"),
      {"key 'mesh.element_type'", "'tet7'"});
}

TEST(RuntimeScene, InstrumentsAreParsedAndToolTopicsFollowTheirTrocar) {
  const RuntimeScene s = parseRuntimeScene(instrumentScene(), "run.yaml");
  ASSERT_EQ(s.tools.size(), 3u);
  ASSERT_EQ(s.trocars.size(), 2u);
  EXPECT_EQ(s.trocars[0].tool, 0);
  EXPECT_EQ(s.trocars[1].tool, 1);
  EXPECT_NEAR(s.trocars[0].X_WF.translation().x(), -0.05, 1e-15);
  EXPECT_NEAR((s.trocars[0].X_WF.linear() * Eigen::Vector3d::UnitZ()).z(), -1.0, 1e-9);
  const ToolSpec& grasper = s.tools[0];
  EXPECT_EQ(grasper.pose_topic, "/trocar_0/tool/pose");
  EXPECT_EQ(grasper.contact_model_topic, "/trocar_0/tissue/contact_model");
  EXPECT_EQ(grasper.wrench_topic, "/trocar_0/tissue/wrench");
  ASSERT_TRUE(grasper.grasp.has_value());
  EXPECT_EQ(grasper.grasp->joint, "trocar_0_grip");
  EXPECT_EQ(grasper.grasp->joint_topic, "joint_states");
  EXPECT_TRUE(grasper.grasp->topic.empty());
  EXPECT_EQ(s.tools[1].contact, ContactResponse::Proxy);
  EXPECT_FALSE(s.tools[1].grasp.has_value());
  const ToolSpec& scalpel = s.tools[2];
  EXPECT_FALSE(scalpel.contact.has_value());
  EXPECT_EQ(scalpel.pose_topic, "tool/pose");
  EXPECT_TRUE(scalpel.wrench_topic.empty());
  ASSERT_EQ(s.blades.size(), 1u);
  EXPECT_EQ(s.blades[0].tool, 2);
  EXPECT_EQ(s.blades[0].edge.cols(), 2);
  ASSERT_TRUE(s.robot.has_value());
  EXPECT_EQ(s.robot->description, "trunk");
  EXPECT_NEAR(s.robot->X_WB.translation().x(), 0.3, 1e-15);
}

TEST(RuntimeScene, EveryInstrumentKeyHasANamedError) {
  const std::string s = instrumentScene();
  expectRejected(replaced(s, "tool: grasper, fulcrum", "tool: forceps, fulcrum"),
                 {"key 'trocars[0].tool'", "no tool is named 'forceps'", "grasper"});
  expectRejected(replaced(s, "tool: probe, fulcrum", "tool: grasper, fulcrum"),
                 {"key 'trocars[1].tool'", "already held by another trocar"});
  expectRejected(replaced(s, "name: trocar_1", "name: trocar_0"),
                 {"key 'trocars[1].name'", "duplicate trocar name"});
  expectRejected(replaced(s, "name: trocar_1", "name: 'trocar 1'"),
                 {"key 'trocars[1].name'", "must start with a letter"});
  expectRejected(replaced(s, "name: trocar_1", "name: world"), {"key 'trocars[1].name'"});
  expectRejected(replaced(s, ", fulcrum: {position: [0.05, 0.0, 0.2]}", ""),
                 {"key 'trocars[1].fulcrum'", "missing required key"});
  expectRejected(replaced(s, "position: [0.05, 0.0, 0.2]", "position: [500, 0.0, 0.2]"),
                 {"key 'trocars[1].fulcrum.position'", "out of range"});
  expectRejected(replaced(s, "fulcrum: {position: [0.05", "pivot: {}, fulcrum: {position: [0.05"),
                 {"key 'trocars[1].pivot'", "unknown key"});
  expectRejected(replaced(s, "{tool: scalpel, edge", "{tool: knife, edge"),
                 {"key 'blades[0].tool'", "no tool is named 'knife'"});
  expectRejected(replaced(s, "edge: [[0, 0, 0], [0, 0, -0.07]]", "edge: [[0, 0, 0]]"),
                 {"key 'blades[0].edge'"});
  expectRejected(replaced(s, "edge: [[0, 0, 0], [0, 0, -0.07]]", "edge: [[0, 0, 0], [0, 0]]"),
                 {"key 'blades[0].edge'", "each point is [x, y, z]"});
  expectRejected(replaced(s, "edge: [[0, 0, 0], [0, 0, -0.07]]", "edge: [[0, 0, 0], [0, 0, 0]]"),
                 {"key 'blades[0].edge'"});
  expectRejected(replaced(s, "description: trunk", "description: 'a b'"),
                 {"key 'robot.description'"});
  expectRejected(replaced(s, "base_pose: {position", "base_pose: {rpy: [9, 0, 0], position"),
                 {"key 'robot.base_pose.rpy'", "out of range"});
  expectRejected(replaced(s, "robot: {description", "robot: {arm: 1, description"),
                 {"key 'robot.arm'", "unknown key"});
  std::string five = std::string(kScene) + "tools:\n";
  for (int i = 0; i < 5; ++i) {
    const std::string n = std::to_string(i);
    five += "  - {name: t" + n + ", pose_topic: t" + n + "/pose, contact: none}\n";
  }
  expectRejected(five, {"key 'tools'", "at most 4 tools"});
  expectRejected(replaced(replaced(kScene, "model: svk", "model: ems"), "resolution: [1, 1, 1]",
                          "resolution: [1, 1, 1], element_type: tet10"),
                 {"key 'model'", "tet4 meshes only"});
}

TEST(RuntimeScene, ToolKeysFollowItsContactKind) {
  const std::string s = instrumentScene();
  expectRejected(replaced(s, "{name: scalpel, contact: none}",
                          "{name: scalpel, contact: none, radius: 0.001}"),
                 {"key 'tools[2].radius'", "touches nothing"});
  expectRejected(
      replaced(s, "proxy_stiffness: 200.0}", "proxy_stiffness: 200.0, coupling_stiffness: 1.0e4}"),
      {"key 'tools[1].coupling_stiffness'", "proxy tool has no coupling"});
  expectRejected(
      replaced(s, "contact: constraint, grasp", "contact: constraint, proxy_stiffness: 5.0, grasp"),
      {"key 'tools[0].proxy_stiffness'", "only a tool with 'contact: proxy'"});
  expectRejected(replaced(s, "contact: proxy, proxy_stiffness: 200.0", "contact: proxy"),
                 {"key 'tools[1].proxy_stiffness'", "missing required key"});
  expectRejected(replaced(s, "grasp: {radius: 0.006}", "grasp: {radius: 0.2}"),
                 {"key 'tools[0].grasp.radius'", "out of range"});
  expectRejected(replaced(s, "grasp: {radius: 0.006}", "grasp: {radius: 0.006, joint_topic: js}"),
                 {"key 'tools[0].grasp.joint_topic'", "give 'joint' too"});
  expectRejected(replaced(s, "grasp: {radius: 0.006}", "grasp: {radius: 0.006, closed_angle: 4}"),
                 {"key 'tools[0].grasp.closed_angle'", "out of range"});
  expectRejected(replaced(s, "grasp: {radius: 0.006}", "grasp: {radius: 0.006, jaw: 1}"),
                 {"key 'tools[0].grasp.jaw'", "unknown key"});
  expectRejected(replaced(s, "name: probe", "name: 'probe 2'"), {"key 'tools[1].name'"});
}

TEST(RuntimeScene, TwoToolsOnOneTopicAreRejected) {
  const std::string two =
      std::string(kScene) +
      "tools:\n  - {name: a, radius: 0.002, shaft_length: 0.05, contact: constraint}\n"
      "  - {name: b, radius: 0.002, shaft_length: 0.05, contact: constraint, "
      "pose_topic: b/pose}\n";
  expectRejected(two, {"key 'tools[1].wrench_topic'", "'tissue/wrench'", "tool 'a'"});
  expectRejected(replaced(two, "pose_topic: b/pose", "pose_topic: tool/pose"),
                 {"key 'tools[1].pose_topic'", "give each tool its own topics"});
}

TEST(RuntimeScene, ToolWithoutContactBuildsNoContactAndHasNoContactModel) {
  RuntimeScene scene = parseRuntimeScene(instrumentScene(), "run.yaml");
  scene.tools.erase(scene.tools.begin(), scene.tools.begin() + 2);
  scene.trocars.clear();
  scene.blades.clear();
  TissueSimulation sim(scene);
  EXPECT_EQ(sim.numTools(), 1);
  for (const std::string& c : sim.components()) EXPECT_NE(c, "contact");
  sim.setToolPose(0, Eigen::Isometry3d::Identity());  // inside the cube: touches nothing
  sim.step();
  EXPECT_FALSE(sim.toolContact(0).in_contact);
  EXPECT_EQ(sim.toolContact(0).f0_S, Eigen::Vector3d::Zero());
}

TEST(RuntimeScene, ConstructedSimulationReportsMeshWarnings) {
  // Sane: a 5 cm cube held at its base.
  EXPECT_TRUE(TissueSimulation(parseRuntimeScene(kScene, "t.yaml")).warnings().empty());
  // No fixed region: the whole cube floats; 500 m cube: absurd scale.
  const std::string floating = replaced(
      kScene, "fixed:\n  - region: {max: [.inf, .inf, 1.0e-9]}\n    components: [z]\n", "");
  const std::vector<std::string> w =
      TissueSimulation(parseRuntimeScene(floating, "t.yaml")).warnings();
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("has no fixed node"), std::string::npos) << w[0];
  const std::vector<std::string> big =
      TissueSimulation(
          parseRuntimeScene(replaced(replaced(kScene, "[0.05, 0.05, 0.05]", "[500, 500, 500]"),
                                     "max: [.inf, .inf, 1.0e-9]", "max: [.inf, .inf, 1.0e-6]"),
                            "t.yaml"))
          .warnings();
  ASSERT_EQ(big.size(), 1u);
  EXPECT_NE(big[0].find("above 100 m"), std::string::npos) << big[0];
}

}  // namespace
}  // namespace surgical_sim::core
