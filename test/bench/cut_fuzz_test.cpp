// The random-sweep cut fuzzer over the organ.
#include "surgical_sim/bench/cut_fuzz.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace surgical_sim::bench {
namespace {

TEST(CutFuzz, RandomSweepsOverTheOrgan) {
  CutFuzzSettings settings;
  settings.sweeps = 200;
  settings.cells_per_axis = 6;
  settings.seed = 20261122;
  const CutFuzzReport r = runCutFuzz(settings);
  EXPECT_EQ(r.failure, "");
  EXPECT_EQ(r.sweeps, 200);
  EXPECT_TRUE(r.finite);
  EXPECT_LE(r.max_mass_error, 1e-12);
  EXPECT_GT(r.min_rest_volume, 0.0);
  EXPECT_GT(r.cut_edges, 0);
  EXPECT_GT(r.components, 1);
}

TEST(CutFuzz, RejectsSettingsWithoutSweeps) {
  EXPECT_THROW(runCutFuzz(CutFuzzSettings{}), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::bench
