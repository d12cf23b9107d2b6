#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

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
    parseBenchmarkScene(yaml, "test.yaml");
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

TEST(BenchmarkScene, ParsesValidSceneWithUnitsAndOpenRegions) {
  const BenchmarkScene s = parseBenchmarkScene(kValidScene, "test.yaml");
  EXPECT_EQ(s.name, "unit");
  EXPECT_DOUBLE_EQ(s.material.young_modulus, 20e3);
  ASSERT_EQ(s.fixed.size(), 1u);
  EXPECT_EQ(s.fixed[0].components, Eigen::Vector3i(0, 0, 1));
  EXPECT_TRUE(s.fixed[0].region.contains(Eigen::Vector3d(1e6, -1e6, 0.0)));
  EXPECT_FALSE(s.fixed[0].region.contains(Eigen::Vector3d(0, 0, 1e-3)));
  EXPECT_EQ(s.models, std::vector<ModelKind>{ModelKind::Svk});
}

TEST(BenchmarkScene, MalformedYamlNamesTheLine) {
  expectRejected("name: x\nmesh: [unclosed\n", {"test.yaml", "malformed YAML", "line"});
}

TEST(BenchmarkScene, MalformedYamlNamesTheEnclosingKey) {
  expectRejected("name: x\nmesh:\n  generator: box\n  size: [1, 2\n",
                 {"test.yaml", "malformed YAML at line", "(in key 'mesh.size')"});
  expectRejected("name: x\ntools:\n  - name: a\n    radius: [0.1: 2]: 3\n",
                 {"test.yaml", "(in key 'tools[].radius')"});
  expectRejected("name: x\nmesh: " + std::string(5000, '[') + std::string(5000, ']') + "\n",
                 {"(in key 'mesh')", "levels deep"});
}

TEST(BenchmarkScene, DeepNestingNamesTheLine) {
  expectRejected("name: x\nmesh: " + std::string(5000, '[') + std::string(5000, ']') + "\n",
                 {"test.yaml", "malformed YAML at line 2", "levels deep"});
}

TEST(BenchmarkScene, MissingKeyIsNamed) {
  expectRejected(replaced(kValidScene, "  density: 1000.0\n", ""),
                 {"material.density", "missing required key"});
}

TEST(BenchmarkScene, TypoKeyIsNamed) {
  expectRejected(replaced(kValidScene, "young_modulus", "young_modulos"),
                 {"material.young_modulos", "unknown key"});
}

TEST(BenchmarkScene, NonNumericValueIsNamed) {
  expectRejected(replaced(kValidScene, "20.0e3", "soft"),
                 {"material.young_modulus", "expected a number", "soft"});
}

TEST(BenchmarkScene, OutOfRangePhysicalParametersAreNamed) {
  expectRejected(replaced(kValidScene, "poisson_ratio: 0.3", "poisson_ratio: 0.5"),
                 {"material.poisson_ratio", "out of range"});
  expectRejected(replaced(kValidScene, "20.0e3", "-5"), {"material.young_modulus"});
  expectRejected(replaced(kValidScene, "time_step: 0.01", "time_step: 5"),
                 {"time_step", "out of range"});
  expectRejected(replaced(kValidScene, "time_step: 0.01", "time_step: .nan"),
                 {"time_step", "expected a number"});
}

TEST(BenchmarkScene, UnknownChoicesAreNamed) {
  expectRejected(replaced(kValidScene, "models: svk", "models: [svk, jelly]"),
                 {"models", "'jelly' is not one of"});
  expectRejected(replaced(kValidScene, "solvers: cholmod", "solvers: lu"), {"solvers", "'lu'"});
  expectRejected(replaced(kValidScene, "generator: box", "generator: sphere"),
                 {"mesh.generator", "sphere"});
}

TEST(BenchmarkScene, BadResolutionsAndRegionsAreNamed) {
  expectRejected(replaced(kValidScene, "[[1, 1, 1]]", "[[0, 1, 1]]"), {"mesh.resolutions"});
  expectRejected(replaced(kValidScene, "[[1, 1, 1]]", "[[1, 1]]"), {"mesh.resolutions"});
  expectRejected(
      replaced(kValidScene, "{max: [.inf, .inf, 1.0e-9]}", "{min: [1, 1, 1], max: [0, 0, 0]}"),
      {"fixed[0].region.min", "min exceeds max"});
}

TEST(BenchmarkScene, UniaxialMeasureNeedsPrescribedMotion) {
  expectRejected(replaced(kValidScene, "  type: self_reference",
                          "  type: uniaxial_svk_force\n  region: {}\n  component: z\n"
                          "  face_area: 0.0025\n  rest_length: 0.05"),
                 {"measure", "prescribed"});
}

TEST(BenchmarkScene, UnknownMeshUnitIsNamed) {
  const std::string scene = replaced(kValidScene,
                                     "  generator: box\n  size: [0.05, 0.05, 0.05]\n"
                                     "  resolutions: [[1, 1, 1]]\n",
                                     "  generator: file\n  file: liver.msh\n  unit: furlong\n");
  expectRejected(scene, {"mesh.unit", "furlong"});
}

TEST(BenchmarkScene, MissingFileIsNamed) {
  try {
    loadBenchmarkScene("/nonexistent/scene.yaml");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
  }
}

TEST(BenchmarkScene, EveryShippedBenchmarkAndRuntimeSceneLoads) {
  const std::string config = std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(config + "bench")) {
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(loadBenchmarkScene(entry.path().string()));
    ++count;
  }
  EXPECT_GE(count, 7);
  count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(config + "scenes")) {
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(loadRuntimeScene(entry.path().string()));
    ++count;
  }
  EXPECT_GE(count, 2);
}

TEST(BenchmarkScene, DuplicateKeysAreRejectedNamingTheKey) {
  expectRejected(replaced(kValidScene, "time_step: 0.01\n", "time_step: 0.01\ntime_step: 0.02\n"),
                 {"test.yaml", "key 'time_step': duplicate key (line"});
  expectRejected(replaced(kValidScene, "  density: 1000.0\n", "  density: 1000.0\n  density: 1\n"),
                 {"key 'material.density': duplicate key"});
  expectRejected(replaced(kValidScene, "{max: [.inf, .inf, 1.0e-9]}",
                          "{max: [.inf, .inf, 1.0e-9], max: [1, 1, 1]}"),
                 {"key 'fixed[0].region.max': duplicate key"});
  expectRejected(replaced(kValidScene, "steps: 1\n", "steps: 1\n[a, b]: 2\n"),
                 {"key '(top level)'", "is not a plain string"});
}

TEST(BenchmarkScene, MalformedIntegersNameTheirKey) {
  expectRejected(replaced(kValidScene, "[[1, 1, 1]]", "[[1.5, 1, 1]]"),
                 {"key 'mesh.resolutions'", "expected an integer in [1, 4096], got 1.5"});
  expectRejected(replaced(kValidScene, "[[1, 1, 1]]", "[[99999999999999999999, 1, 1]]"),
                 {"key 'mesh.resolutions'", "expected an integer"});
  expectRejected(replaced(kValidScene, "[[1, 1, 1]]", "[[x, 1, 1]]"),
                 {"key 'mesh.resolutions'", "expected a number, got 'x'"});
  expectRejected(replaced(kValidScene, "[[1, 1, 1]]", "[[[1], 1, 1]]"),
                 {"key 'mesh.resolutions'", "expected a number"});
  expectRejected(replaced(kValidScene, "steps: 1", "steps: 1e300"),
                 {"key 'steps'", "expected an integer"});
}

TEST(BenchmarkScene, MeshBeyondTheMemoryBudgetIsRejectedBeforeBuilding) {
  // 4096^3 cells pass the per-axis range check but would need terabytes.
  expectRejected(replaced(kValidScene, "[[1, 1, 1]]", "[[4096, 4096, 4096]]"),
                 {"key 'mesh.resolutions'", "resolution [4096, 4096, 4096] with tet4 needs about",
                  "above the budget of 8 GB"});
  expectRejected(replaced(kValidScene, "  resolutions: [[1, 1, 1]]\n",
                          "  resolutions: [[1, 1, 1], [40, 40, 40]]\n"
                          "  element_types: [tet4, tet10]\n"),
                 {"key 'mesh.resolutions'", "[40, 40, 40] with tet10"});
  MeshSpec organ;
  organ.generator = "organ_blob";
  const MeshSizeEstimate e = estimateMeshSize(organ, {8, 0, 0}, ElementType::Tet4);
  EXPECT_EQ(e.nodes, 729.0);  // palpation scene: 9^3 nodes, 6 * 8^3 tets
  EXPECT_EQ(e.elements, 3072.0);
  EXPECT_TRUE(meshBudgetProblem(organ, {24, 0, 0}, ElementType::Tet4).empty());
}

TEST(BenchmarkScene, OverlongListsAreRejected) {
  std::string factors = "load_factors: [0.1";
  for (int i = 0; i < 10000; ++i) factors += ", 0.1";
  expectRejected(replaced(kValidScene, "steps: 1\n", "steps: 1\n" + factors + "]\n"),
                 {"key 'load_factors'", "10001 entries, more than the limit of 10000"});
}

TEST(BenchmarkScene, MeshUnitIsCheckedForGeneratedMeshes) {
  expectRejected(replaced(kValidScene, "  generator: box\n", "  generator: box\n  unit: parsec\n"),
                 {"key 'mesh.unit'", "parsec"});
  expectRejected(replaced(kValidScene, "  generator: box\n", "  generator: box\n  unit: mm\n"),
                 {"key 'mesh.unit'", "applies to mesh files only"});
  EXPECT_NO_THROW(parseBenchmarkScene(
      replaced(kValidScene, "  generator: box\n", "  generator: box\n  unit: m\n"), "test.yaml"));
}

TEST(BenchmarkScene, MeshSplitIsAChoiceForBoxAndBeam) {
  EXPECT_EQ(parseBenchmarkScene(kValidScene, "test.yaml").mesh.split, CellSplit::Symmetric);
  const auto with_split = [](const std::string& split) {
    return replaced(kValidScene, "  generator: box\n",
                    "  generator: box\n  split: " + split + "\n");
  };
  EXPECT_EQ(parseBenchmarkScene(with_split("diagonal"), "test.yaml").mesh.split,
            CellSplit::Diagonal);
  EXPECT_EQ(parseBenchmarkScene(with_split("symmetric"), "test.yaml").mesh.split,
            CellSplit::Symmetric);
  expectRejected(with_split("kuhn"),
                 {"key 'mesh.split'", "'kuhn' is not one of", "diagonal", "symmetric"});
  const std::string blob = replaced(
      replaced(kValidScene, "  generator: box\n", "  generator: organ_blob\n  split: diagonal\n"),
      "[[1, 1, 1]]", "[[2, 0, 0]]");
  expectRejected(blob, {"key 'mesh.split'", "box and beam generators only"});
}

TEST(BenchmarkScene, TissuePoseIsBounded) {
  const std::string scene = std::string(kValidScene) + "tissue_pose: {position: P, rpy: R}\n";
  const auto pose = [&](const std::string& p, const std::string& r) {
    return replaced(replaced(scene, "P", p), "R", r);
  };
  expectRejected(pose("[1.0e20, 0, 0]", "[0, 0, 0]"),
                 {"key 'tissue_pose.position'", "out of range"});
  expectRejected(pose("[0, 0, 0]", "[0, 1.0e20, 0]"), {"key 'tissue_pose.rpy'", "out of range"});
  expectRejected(pose("[0, 0, 0]", "[0, .nan, 0]"), {"key 'tissue_pose.rpy'"});
  const BenchmarkScene s =
      parseBenchmarkScene(pose("[0, 0, 60]", "[0, 0, 3.14159265358979]"), "t.yaml");
  EXPECT_TRUE(s.tissue_pose.translation().isApprox(Eigen::Vector3d(0, 0, 60)));
  EXPECT_TRUE(s.tissue_pose.linear().isUnitary(1e-12));
}

TEST(BenchmarkScene, ReferenceFormulaNeedsGravityAndReferenceIsNonZero) {
  const std::string tip = replaced(kValidScene, "  type: self_reference",
                                   "  type: tip_displacement\n  region: {}\n  component: z\n"
                                   "  reference_formula: euler_bernoulli_timoshenko");
  expectRejected(tip, {"key 'gravity'", "needs a non-zero gravity"});
  EXPECT_NO_THROW(
      parseBenchmarkScene(replaced(tip, "steps: 1\n", "steps: 1\ngravity: [0, 0, -9.81]\n"), "t"));
  expectRejected(replaced(tip, "reference_formula: euler_bernoulli_timoshenko", "reference: 0.0"),
                 {"key 'measure.reference'", "must be non-zero"});
}

TEST(BenchmarkScene, ReferenceSolverIsAChoiceOfSelfReferenceMeasures) {
  EXPECT_EQ(parseBenchmarkScene(kValidScene, "t.yaml").measure.reference_solver,
            SolverKind::Cholmod);
  const std::string pcg =
      replaced(kValidScene, "  type: self_reference",
               "  type: self_reference\n  reference_solver: pcg_cholesky_reuse");
  EXPECT_EQ(parseBenchmarkScene(pcg, "t.yaml").measure.reference_solver,
            SolverKind::PcgCholeskyReuse);
  expectRejected(replaced(pcg, "pcg_cholesky_reuse", "lu"),
                 {"key 'measure.reference_solver'", "'lu' is not one of"});
  const std::string measure =
      "  type: tip_displacement\n  region: {}\n  component: z\n"
      "  reference: 0.01\n  reference_solver: cholmod";
  expectRejected(replaced(kValidScene, "  type: self_reference", measure),
                 {"key 'measure.reference_solver'", "only a self_reference measure"});
}

TEST(BenchmarkScene, VariantsLayTheirKeysOverTheFile) {
  const BenchmarkScene s = parseBenchmarkScene(std::string(kValidScene) + R"(
variants:
  - name: before
  - name: after
    solvers: [pcg_cholesky_reuse, pcg_jacobi]
    material: {young_modulus: 40.0e3}
    pcg: {tolerance: 1.0e-8}
)",
                                               "t.yaml");
  ASSERT_EQ(s.variants.size(), 2u);
  const BenchmarkScene& before = s.variants[0].scene;
  const BenchmarkScene& after = s.variants[1].scene;
  EXPECT_EQ(s.variants[0].name, "before");
  EXPECT_EQ(s.variants[1].name, "after");
  EXPECT_EQ(before.solvers, s.solvers);
  EXPECT_DOUBLE_EQ(before.material.young_modulus, 20e3);
  EXPECT_TRUE(before.variants.empty());
  // A list replaces; a map merges key by key (the density and Poisson ratio stay).
  EXPECT_EQ(after.solvers,
            (std::vector<SolverKind>{SolverKind::PcgCholeskyReuse, SolverKind::PcgJacobi}));
  EXPECT_DOUBLE_EQ(after.material.young_modulus, 40e3);
  EXPECT_DOUBLE_EQ(after.material.poisson_ratio, 0.3);
  EXPECT_DOUBLE_EQ(after.material.density, 1000.0);
  EXPECT_DOUBLE_EQ(after.pcg_tolerance, 1e-8);
  EXPECT_EQ(after.name, "unit");
  EXPECT_TRUE(s.variants[0].keys.empty());
  EXPECT_FALSE(before.threads);
  EXPECT_EQ(s.variants[1].keys,
            (std::vector<std::string>{"solvers", "material.young_modulus", "pcg.tolerance"}));
}

TEST(BenchmarkScene, BadVariantsAreNamed) {
  const std::string base(kValidScene);
  expectRejected(base + "variants: []\n", {"key 'variants'", "at least one"});
  expectRejected(base + "variants: [{name: a, threads: 0}]\n",
                 {"key 'variants[0].name'", "key 'threads'"});
  EXPECT_EQ(*parseBenchmarkScene(base + "threads: 2\n", "t.yaml").threads, 2);
  expectRejected(base + "variants: [{name: a}, {name: a}]\n",
                 {"key 'variants[1].name'", "duplicate variant name 'a'"});
  expectRejected(base + "variants: [{name: 2x}]\n", {"key 'variants[0].name'"});
  expectRejected(base + "variants: [{name: a, solvers: [lu]}]\n",
                 {"key 'variants[0].name'", "variant 'a'", "key 'solvers'", "'lu'"});
  expectRejected(base + "variants: [{name: a, variants: [{name: b}]}]\n",
                 {"key 'variants[0].variants'", "cannot have variants"});
}

TEST(BenchmarkScene, LoadPathAndReferencesAreBounded) {
  expectRejected(replaced(kValidScene, "steps: 1\n", "steps: 1\nload_factors: [0.1, 1e20]\n"),
                 {"key 'load_factors'", "1e+20 is out of range [-1000, 1000]"});
  const std::string tip = replaced(kValidScene, "  type: self_reference",
                                   "  type: tip_displacement\n  region: {}\n  component: z\n"
                                   "  reference: 99999999999999999999");
  expectRejected(tip, {"key 'measure.reference'", "out of range"});
  expectRejected(replaced(kValidScene, "fixed:\n",
                          "prescribed:\n  - region: {}\n    displacement: [0, 0, 1e6]\nfixed:\n"),
                 {"key 'prescribed[0].displacement'", "out of range"});
  // A subnormal underflows to (almost) zero and is accepted as a number.
  EXPECT_NO_THROW(parseBenchmarkScene(
      replaced(kValidScene, "steps: 1\n", "steps: 1\ngravity: [0, 1e-320, -9.81]\n"), "t"));
}

TEST(BenchmarkScene, MaterialErrorsNameTheKey) {
  expectRejected(replaced(kValidScene, "poisson_ratio: 0.3", "poisson_ratio: 0.7"),
                 {"key 'material.poisson_ratio'", "out of range"});
  expectRejected(replaced(kValidScene, "density: 1000.0", "density: 1e9"),
                 {"key 'material.density'"});
  try {
    parseBenchmarkScene(replaced(kValidScene, "density: 1000.0", "density: soft"), "test.yaml");
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "scene test.yaml: key 'material.density': expected a number, got 'soft'");
  }
}

TEST(BenchmarkScene, EmptyStringsAndTopicNamesAreRejected) {
  const std::string tools = std::string(kValidScene) +
                            "tools:\n  - name: tool\n    pose_topic: TOPIC\n    radius: 0.002\n"
                            "    shaft_length: 0.05\n    contact: constraint\n";
  expectRejected(replaced(tools, "TOPIC", "''"),
                 {"key 'tools[0].pose_topic'", "must not be empty"});
  expectRejected(replaced(tools, "TOPIC", "'tool pose'"),
                 {"key 'tools[0].pose_topic'", "not a valid ROS topic name"});
  expectRejected(replaced(replaced(tools, "TOPIC", "tool/pose"), "contact: constraint",
                          "contact: constraint\n    wrench_topic: ''"),
                 {"key 'tools[0].wrench_topic'", "must not be empty"});
  expectRejected(replaced(kValidScene, "name: unit", "name: ''"),
                 {"key 'name'", "must not be empty"});
  const BenchmarkScene s =
      parseBenchmarkScene(replaced(tools, "TOPIC", "/arm_1/tip_pose"), "t.yaml");
  EXPECT_EQ(s.tools.at(0).pose_topic, "/arm_1/tip_pose");
}

}  // namespace
}  // namespace surgical_sim::core
