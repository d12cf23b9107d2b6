// Meshless (EFG) cutting of the liver-like body with both cutters: random-sweep fuzz, progressive
// cuts under dynamics and the independence of a cut's cost from the cuts before it.
#include "surgical_sim/bench/efg_cutting.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace surgical_sim::bench {
namespace {

TEST(EfgCutFuzz, RandomSweepsOverTheLiverKeepMassClosureAndSides) {
  EfgCutFuzzSettings settings;
  settings.sweeps = 100;
  settings.seed = 20261126;
  std::vector<int> passed;  // the count after each sweep that passed its checks
  settings.passed = [&](int done) { passed.push_back(done); };
  const EfgCutFuzzReport r = runEfgCutFuzz(settings);
  EXPECT_EQ(r.failure, "");
  EXPECT_EQ(r.sweeps, 100);
  ASSERT_EQ(passed.size(), 100u);
  for (std::size_t i = 0; i < passed.size(); ++i) EXPECT_EQ(passed[i], static_cast<int>(i) + 1);
  EXPECT_LE(r.max_mass_error, 1e-12);
  EXPECT_GT(r.severed_links, 0);
  EXPECT_GT(r.crossed_edges, 0);
  EXPECT_GT(r.planes_checked, 0);  // the side test had cut planes to check
  EXPECT_GE(r.pieces, 1);
}

TEST(EfgCutFuzz, RejectsSettingsWithoutSweeps) {
  EXPECT_THROW(runEfgCutFuzz(EfgCutFuzzSettings{}), std::invalid_argument);
}

// Progressive cuts of the coarse liver (d = 8 mm, 5,120-triangle surface).
EfgCutRunSettings coarseRun(int cuts, int sweeps_per_cut) {
  EfgCutRunSettings settings;
  settings.surface_subdivisions = 4;
  settings.spacing = 0.008;
  settings.front_width = 0.01;
  settings.cuts = cuts;
  settings.sweeps_per_cut = sweeps_per_cut;
  return settings;
}

TEST(EfgProgressiveCuts, DofsAndMassStayWhileTheSurfaceOpens) {
  const EfgCutRunSettings settings = coarseRun(4, 6);
  EfgCutRunInfo info;
  const std::vector<EfgCutSweepRecord> records = runEfgProgressiveCuts(settings, &info);
  ASSERT_EQ(records.size(), 24u);
  int severed = 0, crossed = 0;
  for (const EfgCutSweepRecord& r : records) {
    EXPECT_TRUE(r.finite) << "cut " << r.cut << " sweep " << r.sweep;
    EXPECT_EQ(r.dofs, 3 * info.particles);  // no DOF added
    EXPECT_LE(r.mass_error, 1e-12);
    severed += r.severed_links;
    crossed += r.crossed_edges;
  }
  EXPECT_GT(severed, 0);
  EXPECT_GT(crossed, 0);
  EXPECT_GT(records.back().triangles, info.surface_triangles);  // the cut faces were added
}

TEST(EfgProgressiveCuts, FactorReusingSolverConvergesThroughTheCuts) {
  EfgCutRunSettings settings = coarseRun(3, 4);
  settings.solver = SolverKind::PcgCholeskyWarped;
  settings.settle_steps = 4;
  EfgCutRunInfo info;
  const std::vector<EfgCutSweepRecord> records = runEfgProgressiveCuts(settings, &info);
  ASSERT_EQ(records.size(), 12u);
  EXPECT_GT(info.settled_step_ms, 0.0);
  int changed = 0;
  for (const EfgCutSweepRecord& r : records) {
    EXPECT_TRUE(r.finite) << "cut " << r.cut << " sweep " << r.sweep;  // converged to tolerance
    EXPECT_GE(r.linear_iterations, 1);
    // The phases are parts of the step, each of them timed.
    EXPECT_GT(r.phases.forces, 0.0);
    EXPECT_GT(r.phases.linear_solve, 0.0);
    EXPECT_LE(1e3 * r.phases.sum(), r.step_ms);
    changed += r.changed_ips;
  }
  EXPECT_GT(changed, 0);
}

// Hostile blade: each cut spans the body and goes through it in one sweep (three pieces can
// come loose at once), under the kept, warped factor. Every step must converge, stay finite and
// move the liver (75 x 50 x 30 mm, sagging under gravity) by less than its own length.
TEST(EfgProgressiveCuts, ThroughCutsInOneSweepUnderTheKeptFactorStayOkAndBounded) {
  EfgCutRunSettings settings = coarseRun(4, 1);
  settings.blade_length = 0.0;  // spans the body
  settings.depth = 2.0;         // through it
  settings.solver = SolverKind::PcgCholeskyWarped;
  EfgCutRunInfo info;
  const std::vector<EfgCutSweepRecord> records = runEfgProgressiveCuts(settings, &info);
  ASSERT_EQ(records.size(), 4u);
  for (const EfgCutSweepRecord& r : records) {
    EXPECT_TRUE(r.finite) << "cut " << r.cut;
    EXPECT_LT(r.max_displacement, 0.15) << "cut " << r.cut;
    EXPECT_EQ(r.dofs, 3 * info.particles);
    EXPECT_LE(r.mass_error, 1e-12);
  }
  EXPECT_GT(records.back().pieces, 1);
}

TEST(EfgProgressiveCuts, RejectsBadSettingsByName) {
  const auto expectNamed = [](const EfgCutRunSettings& settings, const std::string& name) {
    try {
      runEfgProgressiveCuts(settings);
      ADD_FAILURE() << "no throw for " << name;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  EfgCutRunSettings settings;
  settings.depth = 3.0;
  expectNamed(settings, "depth");
  settings.depth = 0.5;
  settings.settle_steps = -1;
  expectNamed(settings, "settle_steps");
  settings.settle_steps = 0;
  settings.spacing = -1.0;
  expectNamed(settings, "spacing");
}

// The same probe cuts on a fresh body and on one cut before in its other half: the background
// cuts reach only their half, the probes cut both bodies alike.
TEST(EfgCutIndependence, BackgroundCutsStayInTheirHalfAndTheProbesCutBothBodiesAlike) {
  EfgCutRunSettings settings = coarseRun(2, 5);
  settings.simulate = false;
  settings.blade_length = 0.02;
  settings.depth = 0.4;
  EfgCutIndependenceInfo info;
  const std::vector<EfgProbeSweepRecord> records = runEfgCutIndependence(settings, 4, &info);
  ASSERT_EQ(records.size(), 10u);
  EXPECT_GT(info.background_triangles, info.run.surface_triangles);  // the background cut
  int severed = 0, crossed = 0;
  for (const EfgProbeSweepRecord& r : records) {
    const auto at = "cut " + std::to_string(r.cut) + " sweep " + std::to_string(r.sweep);
    EXPECT_EQ(r.body[0].severed_links, r.body[1].severed_links) << at;
    EXPECT_EQ(r.body[0].crossed_edges, r.body[1].crossed_edges) << at;
    EXPECT_EQ(r.body[1].triangles - r.body[0].triangles,
              info.background_triangles - info.run.surface_triangles)
        << at;  // the probes add the same triangles to both
    severed += r.body[0].severed_links;
    crossed += r.body[0].crossed_edges;
  }
  EXPECT_GT(severed, 0);
  EXPECT_GT(crossed, 0);
}

TEST(EfgCutIndependence, RejectsDynamicsAndBladesReachingTheOtherHalf) {
  EfgCutRunSettings settings = coarseRun(1, 1);
  settings.blade_length = 0.02;
  EXPECT_THROW(runEfgCutIndependence(settings, 1), std::invalid_argument);  // simulate
  settings.simulate = false;
  settings.blade_length = 0.8 * settings.semi_axes.x();
  EXPECT_THROW(runEfgCutIndependence(settings, 1), std::invalid_argument);
  settings.blade_length = 0.0;  // spanning the body
  EXPECT_THROW(runEfgCutIndependence(settings, 1), std::invalid_argument);
  settings.blade_length = 0.02;
  EXPECT_THROW(runEfgCutIndependence(settings, -1), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::bench
