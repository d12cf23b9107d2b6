#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "surgical_sim/ros/pose_set_sync.h"

namespace surgical_sim::ros_layer {
namespace {

Eigen::Isometry3d at(double z) { return Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, z)); }

ros::Time stamp(double seconds) { return ros::Time(seconds); }

TEST(PoseSetSync, OneSetPerStampWhateverTheArrivalOrder) {
  PoseSetSync sync(2);
  std::vector<Eigen::Isometry3d> poses;
  int sets = 0;
  // Tool 1 first in even sets, tool 0 first in odd ones: 10 stamps give exactly 10 sets.
  for (int k = 1; k <= 10; ++k) {
    const int first = k % 2;
    EXPECT_EQ(sync.offer(first, stamp(k), at(k)), PoseSetSync::Offer::Accepted);
    EXPECT_FALSE(sync.complete());
    EXPECT_EQ(sync.offer(1 - first, stamp(k), at(-k)), PoseSetSync::Offer::Accepted);
    ASSERT_TRUE(sync.complete());
    EXPECT_EQ(sync.take(poses), stamp(k));
    EXPECT_FALSE(sync.complete());
    EXPECT_DOUBLE_EQ(poses[static_cast<std::size_t>(first)].translation().z(), k);
    EXPECT_DOUBLE_EQ(poses[static_cast<std::size_t>(1 - first)].translation().z(), -k);
    ++sets;
  }
  EXPECT_EQ(sets, 10);
}

TEST(PoseSetSync, SingleToolMakesOneSetPerPose) {
  PoseSetSync sync(1);
  std::vector<Eigen::Isometry3d> poses;
  for (int k = 1; k <= 5; ++k) {
    sync.offer(0, stamp(0.01 * k), at(k));
    ASSERT_TRUE(sync.complete());
    EXPECT_EQ(sync.take(poses), stamp(0.01 * k));
  }
}

TEST(PoseSetSync, SecondPoseOfOneToolReplacesItsWaitingPose) {
  PoseSetSync sync(2);
  std::vector<Eigen::Isometry3d> poses;
  sync.offer(0, stamp(1.0), at(1.0));
  EXPECT_EQ(sync.offer(0, stamp(2.0), at(2.0)), PoseSetSync::Offer::Replaced);
  EXPECT_FALSE(sync.complete());
  sync.offer(1, stamp(1.5), at(3.0));
  ASSERT_TRUE(sync.complete());
  // The set uses each tool's newest pose and carries the newest stamp.
  EXPECT_EQ(sync.take(poses), stamp(2.0));
  EXPECT_DOUBLE_EQ(poses[0].translation().z(), 2.0);
  EXPECT_DOUBLE_EQ(poses[1].translation().z(), 3.0);
}

TEST(PoseSetSync, PosesNotNewerThanTheLastSetOrTheWaitingPoseAreIgnored) {
  PoseSetSync sync(2);
  std::vector<Eigen::Isometry3d> poses;
  sync.offer(0, stamp(1.0), at(1.0));
  sync.offer(1, stamp(1.0), at(1.0));
  sync.take(poses);
  EXPECT_EQ(sync.offer(0, stamp(1.0), at(5.0)), PoseSetSync::Offer::Stale);
  EXPECT_EQ(sync.offer(1, stamp(0.5), at(5.0)), PoseSetSync::Offer::Stale);
  EXPECT_FALSE(sync.complete());
  sync.offer(0, stamp(3.0), at(3.0));
  EXPECT_EQ(sync.offer(0, stamp(2.0), at(2.0)), PoseSetSync::Offer::Stale);  // out of order
  sync.offer(1, stamp(3.0), at(3.0));
  EXPECT_EQ(sync.take(poses), stamp(3.0));
  EXPECT_DOUBLE_EQ(poses[0].translation().z(), 3.0);
}

TEST(PoseSetSync, NeverPosedToolBlocksTheSetAndIsNamed) {
  PoseSetSync sync(3);
  EXPECT_EQ(sync.neverPosed(), (std::vector<int>{0, 1, 2}));
  sync.offer(1, stamp(1.0), at(1.0));
  sync.offer(1, stamp(2.0), at(2.0));
  EXPECT_FALSE(sync.complete());
  EXPECT_EQ(sync.neverPosed(), (std::vector<int>{0, 2}));
}

TEST(PoseSetSync, ResetAllowsTheSameStampsAgain) {
  PoseSetSync sync(1);
  std::vector<Eigen::Isometry3d> poses;
  sync.offer(0, stamp(1.0), at(1.0));
  sync.take(poses);
  sync.reset();
  EXPECT_EQ(sync.lastSetStamp(), ros::Time());
  EXPECT_EQ(sync.neverPosed(), (std::vector<int>{0}));
  EXPECT_EQ(sync.offer(0, stamp(1.0), at(1.0)), PoseSetSync::Offer::Accepted);
  EXPECT_TRUE(sync.complete());
}

TEST(PoseSetSync, RejectsNoTools) { EXPECT_THROW(PoseSetSync(0), std::invalid_argument); }

}  // namespace
}  // namespace surgical_sim::ros_layer
