#include "surgical_sim/ros/real_time_factor.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace surgical_sim::ros_layer {
namespace {

TEST(RealTimeFactor, RatioOfSimulatedToWallTimeOverTheWindow) {
  RealTimeFactor rtf(1.0);
  EXPECT_EQ(rtf.add(10.0, 0.0), 0.0);  // one sample: no time span yet
  // 100 Hz steps of 0.01 s taking 0.01 s of wall time: real time.
  double factor = 0.0;
  for (int k = 1; k <= 200; ++k) factor = rtf.add(10.0 + 0.01 * k, 0.01 * k);
  EXPECT_NEAR(factor, 1.0, 1e-9);
  // Then each 0.01 s step takes 0.0166 s: 60 steps/s, factor 0.6 once the window holds only them.
  for (int k = 1; k <= 200; ++k) factor = rtf.add(12.0 + 0.01 / 0.6 * k, 2.0 + 0.01 * k);
  EXPECT_NEAR(factor, 0.6, 1e-9);
}

TEST(RealTimeFactor, ClearStartsAfreshAndTheWindowIsValidated) {
  RealTimeFactor rtf(0.5);
  rtf.add(0.0, 0.0);
  rtf.add(1.0, 0.1);
  rtf.clear();
  EXPECT_EQ(rtf.add(2.0, 5.0), 0.0);
  EXPECT_NEAR(rtf.add(2.5, 6.0), 2.0, 1e-12);  // faster than real time
  EXPECT_THROW(RealTimeFactor(0.0), std::invalid_argument);
  EXPECT_THROW(RealTimeFactor(-1.0), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::ros_layer
