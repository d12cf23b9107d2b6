#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/scene/scene_config.h"

namespace surgical_sim::core {
namespace {

const char* kValidScene = R"(
name: unit
mesh:
  generator: box
  size: [0.05, 0.05, 0.05]
  resolutions: [[1, 1, 1]]
material:
  young_modulus: 20.0e3
  poisson_ratio: 0.3
  density: 1000.0
models: svk
integrators: quasi_static
solvers: cholmod
time_step: 0.01
steps: 1
fixed:
  - region: {max: [.inf, .inf, 1.0e-9]}
    components: [z]
measure:
  type: self_reference
)";

/// Expects parsing `yaml` to throw std::invalid_argument whose message contains every fragment.
void expectRejected(const std::string& yaml, const std::vector<std::string>& fragments) {
  try {
    parseSceneConfig(yaml, "test.yaml");
    FAIL() << "scene was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << msg;
  }
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return text.replace(pos, from.size(), to);
}

TEST(SceneConfig, ParsesValidSceneWithUnitsAndOpenRegions) {
  const SceneConfig s = parseSceneConfig(kValidScene, "test.yaml");
  EXPECT_EQ(s.name, "unit");
  EXPECT_DOUBLE_EQ(s.material.young_modulus, 20e3);
  ASSERT_EQ(s.fixed.size(), 1u);
  EXPECT_EQ(s.fixed[0].components, Eigen::Vector3i(0, 0, 1));
  EXPECT_TRUE(s.fixed[0].region.contains(Eigen::Vector3d(1e6, -1e6, 0.0)));
  EXPECT_FALSE(s.fixed[0].region.contains(Eigen::Vector3d(0, 0, 1e-3)));
  EXPECT_EQ(s.models, std::vector<std::string>{"svk"});
}

TEST(SceneConfig, MalformedYamlNamesTheLine) {
  expectRejected("name: x\nmesh: [unclosed\n", {"test.yaml", "malformed YAML", "line"});
}

TEST(SceneConfig, MissingKeyIsNamed) {
  expectRejected(replaced(kValidScene, "  density: 1000.0\n", ""),
                 {"material.density", "missing required key"});
}

TEST(SceneConfig, TypoKeyIsNamed) {
  expectRejected(replaced(kValidScene, "young_modulus", "young_modulos"),
                 {"material.young_modulos", "unknown key"});
}

TEST(SceneConfig, NonNumericValueIsNamed) {
  expectRejected(replaced(kValidScene, "20.0e3", "soft"),
                 {"material.young_modulus", "expected a number", "soft"});
}

TEST(SceneConfig, OutOfRangePhysicalParametersAreNamed) {
  expectRejected(replaced(kValidScene, "poisson_ratio: 0.3", "poisson_ratio: 0.5"),
                 {"material.poisson_ratio", "out of range"});
  expectRejected(replaced(kValidScene, "20.0e3", "-5"), {"material.young_modulus"});
  expectRejected(replaced(kValidScene, "time_step: 0.01", "time_step: 5"),
                 {"time_step", "out of range"});
  expectRejected(replaced(kValidScene, "time_step: 0.01", "time_step: .nan"),
                 {"time_step", "expected a number"});
}

TEST(SceneConfig, UnknownChoicesAreNamed) {
  expectRejected(replaced(kValidScene, "models: svk", "models: [svk, jelly]"),
                 {"models", "'jelly' is not one of"});
  expectRejected(replaced(kValidScene, "solvers: cholmod", "solvers: lu"), {"solvers", "'lu'"});
  expectRejected(replaced(kValidScene, "generator: box", "generator: sphere"),
                 {"mesh.generator", "sphere"});
}

TEST(SceneConfig, BadResolutionsAndRegionsAreNamed) {
  expectRejected(replaced(kValidScene, "[[1, 1, 1]]", "[[0, 1, 1]]"), {"mesh.resolutions"});
  expectRejected(replaced(kValidScene, "[[1, 1, 1]]", "[[1, 1]]"), {"mesh.resolutions"});
  expectRejected(
      replaced(kValidScene, "{max: [.inf, .inf, 1.0e-9]}", "{min: [1, 1, 1], max: [0, 0, 0]}"),
      {"fixed[0].region.min", "min exceeds max"});
}

TEST(SceneConfig, UniaxialMeasureNeedsPrescribedMotion) {
  expectRejected(replaced(kValidScene, "  type: self_reference",
                          "  type: uniaxial_svk_force\n  region: {}\n  component: z\n"
                          "  face_area: 0.0025\n  rest_length: 0.05"),
                 {"measure", "prescribed"});
}

TEST(SceneConfig, UnknownMeshUnitIsNamed) {
  const std::string scene = replaced(kValidScene,
                                     "  generator: box\n  size: [0.05, 0.05, 0.05]\n"
                                     "  resolutions: [[1, 1, 1]]\n",
                                     "  generator: file\n  file: liver.msh\n  unit: furlong\n");
  expectRejected(scene, {"mesh.unit", "furlong"});
}

TEST(SceneConfig, MissingFileIsNamed) {
  try {
    loadSceneConfig("/nonexistent/scene.yaml");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
  }
}

TEST(SceneConfig, EveryShippedSceneLoads) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(
           std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/scenes")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(loadSceneConfig(entry.path().string()));
    ++count;
  }
  EXPECT_GE(count, 5);
}

}  // namespace
}  // namespace surgical_sim::core
