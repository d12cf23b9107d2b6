#include "surgical_sim/core/haptics/local_contact_model.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace surgical_sim::core {
namespace {

LocalContactSample wallSample(double stamp) {
  LocalContactSample s;
  s.stamp = stamp;
  s.p0_W = Eigen::Vector3d(0.0, 0.0, -0.002);  // 2 mm into a wall z < 0, normal +z
  s.f0_W = Eigen::Vector3d(0.0, 0.0, 1.0);     // 500 N/m * 2 mm
  s.K_W = Eigen::Vector3d(0.0, 0.0, -500.0).asDiagonal();
  return s;
}

TEST(LocalContactModel, FreshModelIsTheLinearExpansion) {
  LocalContactModel model(LocalContactSettings{});
  EXPECT_EQ(model.evaluate(Eigen::Vector3d::Zero(), 0.0).status, ContactStatus::NoModel);
  model.update(wallSample(1.0));
  const ContactEvaluation e = model.evaluate(Eigen::Vector3d(0.01, 0.0, -0.004), 1.02);
  EXPECT_EQ(e.status, ContactStatus::Fresh);
  EXPECT_NEAR(e.age, 0.02, 1e-12);
  EXPECT_NEAR(e.force_W.z(), 2.0, 1e-12);  // 1 N + 500 N/m * 2 mm deeper
  EXPECT_NEAR(e.force_W.x(), 0.0, 1e-15);  // tangential motion, no tangential stiffness
  EXPECT_EQ(e.weight, 1.0);
  EXPECT_TRUE(e.stiffness_W.isApprox(wallSample(0).K_W));
}

TEST(LocalContactModel, ExpansionNeverPullsTheToolIntoTheTissue) {
  LocalContactModel model(LocalContactSettings{});
  model.update(wallSample(0.0));  // 1 N at 2 mm depth, 500 N/m: the expansion vanishes at z = 0
  const ContactEvaluation inside = model.evaluate(Eigen::Vector3d(0.0, 0.0, -0.001), 0.0);
  EXPECT_NEAR(inside.force_W.z(), 0.5, 1e-12);
  EXPECT_FALSE(inside.separated);
  // 3 mm above p0 the expansion would be 1 N - 1.5 N = -0.5 N (adhesion): rendered as zero.
  const ContactEvaluation outside = model.evaluate(Eigen::Vector3d(0.0, 0.0, 0.001), 0.0);
  EXPECT_TRUE(outside.separated);
  EXPECT_EQ(outside.status, ContactStatus::Fresh);
  EXPECT_TRUE(outside.force_W.isZero(0.0));
  EXPECT_TRUE(outside.stiffness_W.isZero(0.0));
}

TEST(LocalContactModel, StaleModelFadesLinearlyToZero) {
  LocalContactSettings settings;
  settings.max_age = 0.1;
  settings.fade_time = 0.05;
  LocalContactModel model(settings);
  model.update(wallSample(0.0));
  const Eigen::Vector3d p = wallSample(0).p0_W;
  EXPECT_EQ(model.evaluate(p, 0.1).status, ContactStatus::Fresh);
  const ContactEvaluation half = model.evaluate(p, 0.125);
  EXPECT_EQ(half.status, ContactStatus::Stale);
  EXPECT_NEAR(half.weight, 0.5, 1e-12);
  EXPECT_NEAR(half.force_W.z(), 0.5, 1e-12);
  const ContactEvaluation gone = model.evaluate(p, 0.3);
  EXPECT_EQ(gone.status, ContactStatus::Stale);
  EXPECT_TRUE(gone.force_W.isZero(0.0));
  EXPECT_TRUE(gone.stiffness_W.isZero(0.0));
}

TEST(LocalContactModel, HoldPolicyKeepsTheForceButFlagsIt) {
  LocalContactSettings settings;
  settings.stale_policy = StalePolicy::Hold;
  LocalContactModel model(settings);
  model.update(wallSample(0.0));
  const ContactEvaluation e = model.evaluate(wallSample(0).p0_W, 10.0);
  EXPECT_EQ(e.status, ContactStatus::Stale);
  EXPECT_NEAR(e.force_W.z(), 1.0, 1e-15);
}

TEST(LocalContactModel, NonFiniteModelOrPointGivesZeroForceAndFlag) {
  LocalContactModel model(LocalContactSettings{});
  LocalContactSample bad = wallSample(0.0);
  bad.K_W(1, 1) = std::nan("");
  model.update(bad);
  ContactEvaluation e = model.evaluate(Eigen::Vector3d::Zero(), 0.0);
  EXPECT_EQ(e.status, ContactStatus::NonFinite);
  EXPECT_TRUE(e.force_W.isZero(0.0));
  model.update(wallSample(0.0));
  e = model.evaluate(Eigen::Vector3d(0.0, std::nan(""), 0.0), 0.0);
  EXPECT_EQ(e.status, ContactStatus::NonFinite);
  EXPECT_TRUE(e.force_W.isZero(0.0));
  e = model.evaluate(Eigen::Vector3d(1e308, 0.0, -1e308), 0.0);  // overflows to Inf
  EXPECT_EQ(e.status, ContactStatus::NonFinite);
  EXPECT_TRUE(e.force_W.allFinite());
}

TEST(LocalContactModel, InvalidSettingsThrowNamingTheParameter) {
  LocalContactSettings s;
  s.max_age = 0.0;
  try {
    LocalContactModel model(s);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "haptics.contact.max_age = 0 s is out of range: must be finite and > 0");
  }
  s = LocalContactSettings{};
  s.fade_time = -1.0;
  EXPECT_THROW(LocalContactModel{s}, std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
