// The 'efg' keys of scene files: parsed with their defaults, every bad value rejected naming
// the dotted key, an efg runtime scene.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "efg_test_scene.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace surgical_sim::core {
namespace {

using test::kEfgBench;
using test::replaced;

void expectRejected(const std::string& yaml, const std::vector<std::string>& fragments) {
  try {
    parseBenchmarkScene(yaml, "efg.yaml");
    FAIL() << "scene was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << msg;
  }
}

TEST(EfgSceneKeys, ParsedWithDefaults) {
  const BenchmarkScene s = parseBenchmarkScene(kEfgBench, "efg.yaml");
  EXPECT_EQ(s.models, std::vector<ModelKind>{ModelKind::Efg});
  EXPECT_DOUBLE_EQ(s.efg.spacing, 0.0025);
  const BenchmarkScene d = parseBenchmarkScene(
      replaced(kEfgBench,
               "  neighbours: 8\n  kernel_support: 3.0\n  volume_samples: 4\n  rotation: polar\n",
               ""),
      "efg.yaml");
  EXPECT_EQ(d.efg.neighbours, 8);
  EXPECT_DOUBLE_EQ(d.efg.kernel_support, 3.0);
  EXPECT_EQ(d.efg.volume_samples, 4);
  EXPECT_EQ(d.efg.rotation, EfgRotation::Polar);
  const BenchmarkScene sm = parseBenchmarkScene(
      replaced(kEfgBench, "rotation: polar", "rotation: shape_matching"), "efg.yaml");
  EXPECT_EQ(sm.efg.rotation, EfgRotation::ShapeMatching);
  EXPECT_TRUE(d.efg.ip_at_centroid);
  const BenchmarkScene centre = parseBenchmarkScene(
      replaced(kEfgBench, "rotation: polar", "integration_point: centre"), "efg.yaml");
  EXPECT_FALSE(centre.efg.ip_at_centroid);
  EXPECT_DOUBLE_EQ(d.efg.stabilization, 0.01);
  const BenchmarkScene unstabilized =
      parseBenchmarkScene(replaced(kEfgBench, "rotation: polar", "stabilization: 0"), "efg.yaml");
  EXPECT_EQ(unstabilized.efg.stabilization, 0.0);
  const BenchmarkScene per_resolution = parseBenchmarkScene(
      replaced(kEfgBench, "spacing: 0.0025", "spacing: [0.005, 0.0025]"), "efg.yaml");
  EXPECT_EQ(per_resolution.efg_spacings, (std::vector<double>{0.005, 0.0025}));
  EXPECT_EQ(d.efg_max_cut_triangles, 1000000);
  const BenchmarkScene budget = parseBenchmarkScene(
      replaced(kEfgBench, "rotation: polar", "max_cut_triangles: 5000"), "efg.yaml");
  EXPECT_EQ(budget.efg_max_cut_triangles, 5000);
}

TEST(EfgSceneKeys, EveryKeyRejectsBadValuesNamingIt) {
  expectRejected(replaced(kEfgBench, "spacing: 0.0025", "spacing: -1"), {"efg.spacing", "m"});
  expectRejected(replaced(kEfgBench, "spacing: 0.0025", "spacing: 20"), {"efg.spacing"});
  expectRejected(replaced(kEfgBench, "spacing: 0.0025", "spacing: fine"), {"efg.spacing"});
  expectRejected(replaced(kEfgBench, "spacing: 0.0025", "spacing: [0.01, 0.005, 0.002]"),
                 {"efg", "one per mesh.resolutions"});
  expectRejected(replaced(kEfgBench, "neighbours: 8", "neighbours: 4"), {"efg.neighbours"});
  expectRejected(replaced(kEfgBench, "neighbours: 8", "neighbours: 17"), {"efg.neighbours"});
  expectRejected(replaced(kEfgBench, "kernel_support: 3.0", "kernel_support: 1.0"),
                 {"efg.kernel_support"});
  expectRejected(replaced(kEfgBench, "volume_samples: 4", "volume_samples: 0"),
                 {"efg.volume_samples"});
  expectRejected(replaced(kEfgBench, "volume_samples: 4", "volume_samples: 9"),
                 {"efg.volume_samples"});
  expectRejected(replaced(kEfgBench, "rotation: polar", "rotation: euler"),
                 {"efg.rotation", "'euler'"});
  expectRejected(replaced(kEfgBench, "rotation: polar", "integration_point: middle"),
                 {"efg.integration_point", "'middle'"});
  expectRejected(replaced(kEfgBench, "rotation: polar", "stabilization: 1.5"),
                 {"efg.stabilization", "[0, 1]"});
  expectRejected(replaced(kEfgBench, "rotation: polar", "stabilization: -0.1"),
                 {"efg.stabilization"});
  expectRejected(replaced(kEfgBench, "rotation: polar", "max_cut_triangles: 99"),
                 {"efg.max_cut_triangles"});
  expectRejected(replaced(kEfgBench, "rotation: polar", "max_cut_triangles: 2.5e8"),
                 {"efg.max_cut_triangles"});
  expectRejected(replaced(kEfgBench, "rotation: polar", "max_cut_triangles: many"),
                 {"efg.max_cut_triangles"});
  expectRejected(replaced(kEfgBench, "rotation: polar", "rotation: polar\n  grid: 3"),
                 {"efg", "grid"});
  // Model efg without the efg map.
  const std::string no_efg = kEfgBench;
  expectRejected(no_efg.substr(0, no_efg.find("efg:\n")), {"efg", "spacing"});
}

TEST(EfgSceneKeys, RuntimeSimulationRunsEfgWithBlades) {
  const char* runtime = R"(
name: efg_run
mesh:
  generator: box
  size: [0.05, 0.05, 0.05]
  resolution: [2, 2, 2]
material: {young_modulus: 5.0e3, poisson_ratio: 0.45, density: 1000.0}
model: efg
integrator: implicit_euler_linearized
solver: cholmod
time_step: 0.01
efg: {spacing: 0.0125}
)";
  const RuntimeScene scene = parseRuntimeScene(runtime, "run.yaml");
  EXPECT_EQ(scene.model, ModelKind::Efg);
  TissueSimulation sim(scene);
  EXPECT_EQ(sim.model().name(), "efg");
  EXPECT_EQ(sim.step().report.status, StepStatus::Ok);
  RuntimeScene cutting = scene;
  cutting.blades.emplace_back();
  TissueSimulation cut(cutting);
  EXPECT_EQ(cut.step().report.status, StepStatus::Ok);
  EXPECT_EQ(cut.numComponents(), 1);
}

}  // namespace
}  // namespace surgical_sim::core
