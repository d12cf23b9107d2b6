// The liver-like EFG runtime scene (config/scenes/liver_efg.yaml): a closed procedural surface of
// 20k triangles fills the efg model's cells and follows its particles; a tool presses and lets go.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/mesh/surface_closure.h"
#include "surgical_sim/core/mesh/surface_inside.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"
#include "surgical_sim/core/tissue/efg_model.h"

namespace surgical_sim::core {
namespace {

std::string liverPath() {
  return std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/scenes/liver_efg.yaml";
}

/// Tool pointing down (z_T = -z_S) with its tip at p.
Eigen::Isometry3d toolAt(const Eigen::Vector3d& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  X.translation() = p;
  return X;
}

TEST(LiverEfgScene, ClosedFineSurfaceFillsTheModelAndFollowsItAtRest) {
  const RuntimeScene scene = loadRuntimeScene(liverPath());
  TissueSimulation sim(scene);
  const SurfaceMesh& surface = sim.surface();
  EXPECT_GE(surface.triangles.cols(), 20000);
  const SurfaceClosure closure = checkSurfaceClosure(surface.triangles);
  EXPECT_EQ(closure.open_edges, 0);
  EXPECT_EQ(closure.pinched_edges, 0);
  // Every vertex is mapped, and at rest the mapping reproduces the vertices' rest positions.
  const int vertices = sim.mesh().numNodes();
  EXPECT_EQ(static_cast<int>(sim.surfaceMapping().vertices().size()), vertices);
  const Eigen::Map<const Eigen::VectorXd> rest(sim.mesh().nodes.data(), 3 * vertices);
  EXPECT_LT((sim.surfacePositions() - rest).cwiseAbs().maxCoeff(), 1e-12);
  // The model's inside volume is the volume the surface encloses (cells sampled 4^3 times).
  const auto& efg = dynamic_cast<const EfgModel&>(sim.model());
  TriMesh body{sim.mesh().nodes, surface.triangles};
  const double volume = enclosedVolume(body);
  EXPECT_NEAR(efg.grid().volumes.sum(), volume, 0.01 * volume);
  // Particles every 10 mm: far coarser than the surface.
  EXPECT_LT(efg.numNodes(), vertices / 4);
  RecordProperty("particles", efg.numNodes());
  RecordProperty("integration_points", static_cast<int>(efg.grid().volumes.size()));
}

TEST(LiverEfgScene, ToolPressIsFiniteAndItsForceVanishesAfterRelease) {
  TissueSimulation sim(loadRuntimeScene(liverPath()));
  // Top of the right lobe: the highest surface vertex.
  Eigen::Index top = 0;
  sim.mesh().nodes.row(2).maxCoeff(&top);
  const Eigen::Vector3d p = sim.mesh().nodes.col(top);
  const double radius = sim.scene().tools.front().radius;
  const Eigen::Vector3d above = p + Eigen::Vector3d(0.0, 0.0, radius + 0.01);
  sim.setToolPose(0, toolAt(above));
  for (int k = 0; k < 10; ++k) EXPECT_EQ(sim.step().report.status, StepStatus::Ok);
  EXPECT_FALSE(sim.toolContact(0).in_contact);
  // Press 6 mm below where the top was, in 1 mm steps, then hold.
  double force = 0.0;
  for (int k = 1; k <= 30; ++k) {
    const double depth = std::min(k, 6) * 0.001;
    sim.setToolPose(0, toolAt(p + Eigen::Vector3d(0.0, 0.0, radius - depth)));
    const SimulationStepStats s = sim.step();
    EXPECT_TRUE(s.report.status == StepStatus::Ok) << toString(s.report.status) << " step " << k;
    ASSERT_TRUE(sim.state().x.allFinite());
    ASSERT_TRUE(sim.surfacePositions().allFinite());
    force = sim.toolContact(0).f0_S.z();
  }
  EXPECT_TRUE(sim.toolContact(0).in_contact);
  EXPECT_GT(force, 0.01);  // the tissue pushes the tool up [N]
  EXPECT_LT(force, sim.scene().tools.front().max_force);
  RecordProperty("press_force_N", std::to_string(force));
  // Release: the tool goes back above the organ; no contact force remains.
  sim.setToolPose(0, toolAt(above + Eigen::Vector3d(0.0, 0.0, 0.02)));
  for (int k = 0; k < 10; ++k) EXPECT_EQ(sim.step().report.status, StepStatus::Ok);
  EXPECT_FALSE(sim.toolContact(0).in_contact);
  EXPECT_EQ(sim.toolContact(0).f0_S.norm(), 0.0);
  EXPECT_EQ(sim.appliedContactForce().norm(), 0.0);
  EXPECT_TRUE(sim.state().x.allFinite());
}

/// The scene file's text with `from` replaced by `to`.
std::string liverText(const std::string& from, const std::string& to) {
  std::ifstream in(liverPath());
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return text.replace(pos, from.size(), to);
}

void expectKeyError(const std::string& text, const std::string& key) {
  try {
    parseRuntimeScene(text, "liver.yaml");
    ADD_FAILURE() << "accepted, expected an error on " << key;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("key '" + key + "'"), std::string::npos) << e.what();
  }
}

TEST(LiverEfgScene, RejectsATetModelTetElementsAndTooManySubdivisions) {
  expectKeyError(liverText("model: efg", "model: corotational"), "model");
  expectKeyError(liverText("resolution: [5, 0, 0]", "resolution: [5, 0, 0]\n  element_type: tet10"),
                 "mesh.element_type");
  expectKeyError(liverText("resolution: [5, 0, 0]", "resolution: [9, 0, 0]"), "mesh.resolution");
  expectKeyError(liverText("size: [0.09, 0.06, 0.05]", "size: [0.09, 0.0, 0.05]"), "mesh.size");
  try {
    parseBenchmarkScene(R"(
name: liver_bench
mesh: {generator: liver, size: [0.09, 0.06, 0.05], resolutions: [[3, 0, 0]]}
material: {young_modulus: 5.0e3, poisson_ratio: 0.45, density: 1000.0}
models: [efg]
efg: {spacing: 0.005}
integrators: quasi_static
solvers: cholmod
time_step: 1.0
steps: 1
measure: {type: self_reference}
)",
                        "liver_bench.yaml");
    ADD_FAILURE() << "a benchmark file accepted the liver surface";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("key 'mesh.generator'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace surgical_sim::core
