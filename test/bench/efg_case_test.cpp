// An efg benchmark case run end to end: measured at the mesh nodes through the interpolation.
#include <gtest/gtest.h>

#include <vector>

#include "../core/scene/efg_test_scene.h"
#include "surgical_sim/bench/tissue_case.h"
#include "surgical_sim/core/scene/scene_config.h"

namespace surgical_sim::bench {
namespace {

using test::kEfgBench;
using test::replaced;

TEST(EfgCase, BenchmarkCaseRunsAndMeasuresAtTheMeshNodes) {
  const BenchmarkScene scene = parseBenchmarkScene(kEfgBench, "efg.yaml");
  const std::vector<CaseSpec> cases = expandSweep(scene);
  ASSERT_EQ(cases.size(), 2u);
  const CaseResult r = runTissueCase(scene, cases.front());
  EXPECT_EQ(r.status, StepStatus::Ok);
  // 0.1 x 0.02 x 0.02 m at d = 2.5 mm: 40 x 8 x 8 cells, particles every 5 mm.
  EXPECT_EQ(r.elements, 40 * 8 * 8);
  EXPECT_EQ(r.nodes, 21 * 5 * 5);
  EXPECT_LT(r.reference, 0.0);
  EXPECT_LT(r.error_rel, 0.05);
  // More neighbours and shape matching: still a regular (solvable) stiffness; the wider MLS fit
  // is stiffer in bending.
  const BenchmarkScene wide =
      parseBenchmarkScene(replaced(replaced(kEfgBench, "neighbours: 8", "neighbours: 16"),
                                   "rotation: polar", "rotation: shape_matching"),
                          "efg.yaml");
  const CaseResult w = runTissueCase(wide, cases.front());
  EXPECT_EQ(w.status, StepStatus::Ok);
  EXPECT_LT(w.error_rel, 0.2);
}

}  // namespace
}  // namespace surgical_sim::bench
