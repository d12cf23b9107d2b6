#include <gtest/gtest.h>

#include "surgical_sim/core/cutting/fragment_volume.h"

namespace surgical_sim::core {
namespace {

Eigen::Matrix<double, 3, 4> unitTet() {
  Eigen::Matrix<double, 3, 4> X;
  X << 0, 1, 0, 0,  //
      0, 0, 1, 0,   //
      0, 0, 0, 1;
  return X;
}

TEST(FragmentVolume, LocalEdgeIndexFollowsTheTableInBothOrders) {
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(tetLocalEdge(kTetLocalEdges[k][0], kTetLocalEdges[k][1]), k);
    EXPECT_EQ(tetLocalEdge(kTetLocalEdges[k][1], kTetLocalEdges[k][0]), k);
  }
}

TEST(FragmentVolume, CornerCutOffByThePlaneXEqualsHalfIsAnEighth) {
  // Plane x = 0.5 cuts corner 1 = (1,0,0) off at the midpoints of its edges (s measured from
  // the lower corner: edge (0,1) at 0.5, edges (1,2) and (1,3) at 0.5).
  std::array<double, 6> s{0.5, 0, 0, 0.5, 0.5, 0};
  const auto f = fragmentVolumeFractions(unitTet(), s, {0b0010, 0b1101, 0, 0}, 2);
  EXPECT_NEAR(f[0], 0.125, 1e-12);
  EXPECT_NEAR(f[1], 0.875, 1e-12);
}

TEST(FragmentVolume, PairCutByAnObliquePlaneMatchesTheIntegral) {
  // Plane x + y = 0.4 separates {0, 3} from {1, 2}. Volume of x + y < 0.4 in the unit tet:
  // integral_0^0.4 w (1 - w) dw = 0.08 - 0.064 / 3; the tet volume is 1/6.
  std::array<double, 6> s{};
  s[tetLocalEdge(0, 1)] = 0.4;
  s[tetLocalEdge(0, 2)] = 0.4;
  s[tetLocalEdge(1, 3)] = 0.6;  // (1 - t, 0, t): 1 - t = 0.4
  s[tetLocalEdge(2, 3)] = 0.6;
  const double expected = (0.08 - 0.064 / 3.0) * 6.0;
  const auto f = fragmentVolumeFractions(unitTet(), s, {0b1001, 0b0110, 0, 0}, 2);
  EXPECT_NEAR(f[0], expected, 1e-12);
  EXPECT_NEAR(f[1], 1.0 - expected, 1e-12);
}

TEST(FragmentVolume, ManyFragmentsSumToOneAndTinyOnesAreClamped) {
  std::array<double, 6> s{0.5, 0.5, 0.5, 0.5, 0.5, 0.5};
  const auto four = fragmentVolumeFractions(unitTet(), s, {1, 2, 4, 8}, 4);
  EXPECT_NEAR(four[0] + four[1] + four[2] + four[3], 1.0, 1e-15);
  EXPECT_NEAR(four[0], 0.25, 1e-12);                // all singletons 1/8 before normalization
  std::array<double, 6> at_node{0, 0, 0, 0, 0, 0};  // cut through corner 0
  const auto f = fragmentVolumeFractions(unitTet(), at_node, {0b0001, 0b1110, 0, 0}, 2);
  EXPECT_NEAR(f[0], kMinFragmentFraction / (1.0 + kMinFragmentFraction), 1e-15);
  EXPECT_NEAR(f[0] + f[1], 1.0, 1e-15);
}

}  // namespace
}  // namespace surgical_sim::core
