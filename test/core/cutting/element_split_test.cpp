#include "surgical_sim/core/cutting/element_split.h"

#include <gtest/gtest.h>

#include "surgical_sim/core/cutting/fragment_volume.h"

namespace surgical_sim::core {
namespace {

/// Right tetrahedron [m]: corner 0 at (1, 1, 1), corners 1, 2, 3 at 2 m from it along x, y, z
/// (volume fractions do not depend on the size or position).
const Eigen::Matrix<double, 3, 4> kTet =
    (Eigen::Matrix<double, 3, 4>() << 1, 3, 1, 1, 1, 1, 3, 1, 1, 1, 1, 3).finished();

/// Cut flags with the given local edges cut (all cut points at mid-edge unless set otherwise).
std::array<bool, 6> cutEdges(std::initializer_list<int> edges) {
  std::array<bool, 6> cut{};
  for (int k : edges) cut[k] = true;
  return cut;
}

/// Checks that the masks partition the 4 corners and the fractions sum to 1.
void expectPartitionOfTheVolume(const ElementSplit& split) {
  int all = 0;
  double volume = 0.0;
  for (int f = 0; f < split.count; ++f) {
    EXPECT_NE(split.masks[f], 0) << "fragment " << f;
    EXPECT_EQ(all & split.masks[f], 0) << "fragment " << f << " overlaps another";
    all |= split.masks[f];
    EXPECT_GE(split.fractions[f], kMinFragmentFraction);
    volume += split.fractions[f];
  }
  EXPECT_EQ(all, 0xF);
  EXPECT_NEAR(volume, 1.0, 1e-14);
}

TEST(ElementSplit, UncutElementIsOneFragmentWithAllTheVolume) {
  const ElementSplit split = splitElement(kTet, cutEdges({}), {});
  EXPECT_EQ(split.count, 1);
  EXPECT_EQ(split.masks[0], 0xF);
  EXPECT_DOUBLE_EQ(split.fractions[0], 1.0);
}

TEST(ElementSplit, CornerCutOffKeepsTheVolumeOfTheSmallTet) {
  // Corner 1 cut off by points at s = 0.4 from corner 1 along (1,0), (1,2), (1,3): local edges
  // 0 = (0,1) (parameter from corner 0: 0.6), 3 = (1,2) and 4 = (1,3) (from corner 1: 0.4).
  const std::array<double, 6> s{0.6, 0.0, 0.0, 0.4, 0.4, 0.0};
  const ElementSplit split = splitElement(kTet, cutEdges({0, 3, 4}), s);
  ASSERT_EQ(split.count, 2);
  EXPECT_EQ(split.masks[0], 0b1101);  // fragments ordered by their lowest corner
  EXPECT_EQ(split.masks[1], 0b0010);
  EXPECT_NEAR(split.fractions[1], 0.4 * 0.4 * 0.4, 1e-14);
  expectPartitionOfTheVolume(split);
}

TEST(ElementSplit, CutFrontInsideTheElementDoesNotSplitIt) {
  // Two of the three edges at corner 3 cut: corner 3 stays connected through edge (2,3).
  const std::array<double, 6> s{0.0, 0.0, 0.5, 0.0, 0.5, 0.0};
  const ElementSplit split = splitElement(kTet, cutEdges({2, 4}), s);
  EXPECT_EQ(split.count, 1);
  EXPECT_EQ(split.masks[0], 0xF);
  EXPECT_DOUBLE_EQ(split.fractions[0], 1.0);
}

TEST(ElementSplit, PairSplitsFromPairAndEveryEdgeCutGivesFourFragments) {
  // {0, 1} from {2, 3}: the four edges between the pairs are cut.
  const std::array<double, 6> half{0.5, 0.5, 0.5, 0.5, 0.5, 0.5};
  const ElementSplit pairs = splitElement(kTet, cutEdges({1, 2, 3, 4}), half);
  ASSERT_EQ(pairs.count, 2);
  EXPECT_EQ(pairs.masks[0], 0b0011);
  EXPECT_EQ(pairs.masks[1], 0b1100);
  expectPartitionOfTheVolume(pairs);
  const ElementSplit four = splitElement(kTet, cutEdges({0, 1, 2, 3, 4, 5}), half);
  ASSERT_EQ(four.count, 4);
  for (int f = 0; f < 4; ++f) EXPECT_EQ(four.masks[f], 1 << f);
  expectPartitionOfTheVolume(four);
}

}  // namespace
}  // namespace surgical_sim::core
