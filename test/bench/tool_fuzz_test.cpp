#include "surgical_sim/bench/tool_fuzz.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/scene/multi_body_simulation.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace surgical_sim::bench {
namespace {

/// The grasp scene (palpation organ, one tool with jaws) on a coarse organ.
RuntimeScene smallGraspScene() {
  RuntimeScene scene =
      loadRuntimeScene(std::string(SURGICAL_SIM_SOURCE_DIR) + "/test/data/grasp_scene.yaml");
  scene.resolution = Eigen::Vector3i(5, 0, 0);
  return scene;
}

ToolFuzzSettings shortSettings(const RuntimeScene& scene) {
  ToolFuzzSettings settings;
  settings.steps = 200;
  settings.bad_pose_rate = 0.05;
  settings.grasp_toggle_rate = 0.02;
  settings.force_bounds = sceneForceBounds(scene);
  return settings;
}

/// Sequences of seeds first..last on sim, merged.
template <typename Simulation>
ToolFuzzOutcome runSeeds(Simulation& sim, const ToolFuzzSettings& settings, unsigned first,
                         unsigned last) {
  ToolFuzzOutcome total;
  for (unsigned seed = first; seed <= last; ++seed) {
    std::mt19937 rng(seed);
    total.merge(runToolFuzzSequence(sim, settings, rng));
  }
  return total;
}

TEST(ToolFuzz, HostileMotionStaysFiniteBoundedAndTruthful) {
  const RuntimeScene scene = smallGraspScene();
  TissueSimulation sim(scene);
  const ToolFuzzSettings settings = shortSettings(scene);
  const ToolFuzzOutcome total = runSeeds(sim, settings, 1, 3);
  EXPECT_EQ(total.sequences, 3);
  EXPECT_EQ(total.steps, 600);
  int counted = 0;
  for (const auto& [status, n] : total.status_steps) counted += n;
  EXPECT_EQ(counted, total.steps);
  EXPECT_EQ(total.non_finite_steps, 0);
  // The motion reached the tissue, jumped and grasped; every malformed pose was rejected.
  EXPECT_GT(total.contact_steps, 0);
  EXPECT_GT(total.max_force, 0.0);
  EXPECT_GT(total.teleports, 0);
  EXPECT_GT(total.grasp_toggles, 0);
  EXPECT_GT(total.rejected_poses, 0);
  EXPECT_EQ(total.bad_poses_accepted, 0);
  EXPECT_EQ(total.accepted_poses, total.steps);
  EXPECT_TRUE(std::isfinite(total.max_abs_energy));
  for (const auto& bound : settings.force_bounds) {
    if (!bound) continue;
    EXPECT_LE(total.max_force, *bound * (1.0 + 1e-6));
    EXPECT_EQ(total.over_bound_steps, 0);
    EXPECT_EQ(total.limited_but_ok_steps, 0);
  }
}

/// Scene (b): two organs joined by a connective layer, one tool with jaws. Hostile motion grabs,
/// dives through and yanks the organs; every step is ok or capped, finite and truthful.
TEST(ToolFuzz, MultiBodySceneUnderHostileMotionStaysFiniteBoundedAndTruthful) {
  const RuntimeScene scene = loadRuntimeScene(std::string(SURGICAL_SIM_SOURCE_DIR) +
                                              "/config/scenes/connective_two_organs.yaml");
  MultiBodySimulation sim(scene);
  ToolFuzzSettings settings = shortSettings(scene);
  settings.steps = 150;
  settings.grasp_toggle_rate = 0.05;
  ToolFuzzOutcome total = runSeeds(sim, settings, 1, 2);
  EXPECT_EQ(total.non_finite_steps, 0);
  EXPECT_EQ(total.status_steps["ok"] + total.status_steps["contact_limited"], total.steps);
  EXPECT_GT(total.contact_steps, 0);
  EXPECT_GT(total.grasp_toggles, 0);
  EXPECT_EQ(total.bad_poses_accepted, 0);
  ASSERT_TRUE(settings.force_bounds.at(0).has_value());
  EXPECT_LE(total.max_force, *settings.force_bounds[0] * (1.0 + 1e-6));
  EXPECT_EQ(total.over_bound_steps, 0);
  EXPECT_EQ(total.limited_but_ok_steps, 0);
}

/// Blades sweep through where the tool presses and grasps, on the tet organ (virtual-node cutter)
/// and on the meshless organ: still finite, bounded and truthful, the mass kept, the surface
/// closed, and the cuts changed the topology.
TEST(ToolFuzz, CutsThroughWhereTheToolPressesKeepMassSurfaceAndBounds) {
  for (const std::string& file : {std::string("/test/data/grasp_scene.yaml"),
                                  std::string("/config/scenes/palpation_efg.yaml")}) {
    RuntimeScene scene = loadRuntimeScene(std::string(SURGICAL_SIM_SOURCE_DIR) + file);
    if (scene.model != ModelKind::Efg) scene.resolution = Eigen::Vector3i(5, 0, 0);
    TissueSimulation sim(scene);
    ToolFuzzSettings settings = shortSettings(scene);
    settings.steps = 120;
    settings.cut_rate = 0.3;
    const ToolFuzzOutcome total = runSeeds(sim, settings, 3, 5);
    EXPECT_EQ(total.non_finite_steps, 0) << file;
    EXPECT_EQ(total.over_bound_steps, 0) << file;
    EXPECT_EQ(total.limited_but_ok_steps, 0) << file;
    EXPECT_GT(total.cuts.sweeps, 60) << file;
    EXPECT_GT(total.cuts.changed_steps, 10) << file;
    EXPECT_GT(total.contact_steps, 0) << file;
    EXPECT_LE(total.cuts.max_mass_error, 1e-12) << file;
    EXPECT_EQ(total.cuts.open_surfaces, 0) << file;
  }
  // A multi-body scene takes no blades.
  const RuntimeScene two = loadRuntimeScene(std::string(SURGICAL_SIM_SOURCE_DIR) +
                                            "/config/scenes/connective_two_organs.yaml");
  MultiBodySimulation multi(two);
  ToolFuzzSettings settings = shortSettings(two);
  settings.cut_rate = 0.1;
  std::mt19937 rng(1);
  EXPECT_THROW(runToolFuzzSequence(multi, settings, rng), std::invalid_argument);
}

TEST(ToolFuzz, SameSeedReplaysTheSameSequence) {
  const RuntimeScene scene = smallGraspScene();
  TissueSimulation sim(scene);
  ToolFuzzSettings settings = shortSettings(scene);
  settings.steps = 60;
  std::mt19937 first_rng(7), second_rng(7);
  const ToolFuzzOutcome first = runToolFuzzSequence(sim, settings, first_rng);
  const ToolFuzzOutcome second = runToolFuzzSequence(sim, settings, second_rng);
  EXPECT_EQ(first.max_force, second.max_force);
  EXPECT_EQ(first.max_abs_energy, second.max_abs_energy);
  EXPECT_EQ(first.status_steps, second.status_steps);
  EXPECT_EQ(first.rejected_poses, second.rejected_poses);
  EXPECT_EQ(first.teleports, second.teleports);
}

TEST(ToolFuzz, CountsForcesAboveABoundAndLimitedStepsReportedOk) {
  const RuntimeScene scene = smallGraspScene();
  TissueSimulation sim(scene);
  ToolFuzzSettings settings = shortSettings(scene);
  settings.force_bounds = {1e-9};  // far below any contact force
  std::mt19937 rng(1);
  const ToolFuzzOutcome out = runToolFuzzSequence(sim, settings, rng);
  ASSERT_GT(out.max_force, 1e-9);
  EXPECT_GT(out.over_bound_steps, 0);
  EXPECT_GT(out.limited_but_ok_steps, 0);
  EXPECT_LE(out.limited_but_ok_steps, out.status_steps.at("ok"));
}

TEST(ToolFuzz, RejectsOutOfRangeSettingsNamingThem) {
  const RuntimeScene scene = smallGraspScene();
  TissueSimulation sim(scene);
  std::mt19937 rng(1);
  ToolFuzzSettings settings;
  settings.steps = 0;
  EXPECT_THROW(runToolFuzzSequence(sim, settings, rng), std::invalid_argument);
  settings.steps = 1;
  settings.bad_pose_rate = 1.5;
  try {
    runToolFuzzSequence(sim, settings, rng);
    FAIL() << "bad_pose_rate 1.5 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bad_pose_rate"), std::string::npos);
  }
  settings.bad_pose_rate = 0.0;
  settings.cut_rate = -0.1;
  try {
    runToolFuzzSequence(sim, settings, rng);
    FAIL() << "cut_rate -0.1 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cut_rate"), std::string::npos);
  }
}

}  // namespace
}  // namespace surgical_sim::bench
