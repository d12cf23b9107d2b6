#include "surgical_sim/bench/contact_rate_study.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace surgical_sim::bench {
namespace {

TEST(StiffeningTissue, StiffnessIsTheDerivativeOfTheForce) {
  StiffeningTissue tissue;
  tissue.normal_W = Eigen::Vector3d(1.0, 2.0, -2.0) / 3.0;
  const Eigen::Vector3d p = -0.006 * tissue.normal_W + Eigen::Vector3d(1e-3, 0.0, 2e-3);
  const Eigen::Matrix3d K = tissue.stiffness(p);
  const double h = 1e-7;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(i);
    const Eigen::Vector3d fd = (tissue.force(p + h * e) - tissue.force(p - h * e)) / (2.0 * h);
    EXPECT_LT((K.col(i) - fd).norm(), 1e-5 * K.norm());
  }
}

TEST(ContactRateStudy, LocalLinearModelBeatsZeroOrderHoldAndImprovesWithRate) {
  ContactRateStudySettings s;
  double previous_linear = 1e9;
  for (const double rate : {30.0, 120.0, 500.0}) {
    s.update_rate_hz = rate;
    s.linear_model = false;
    const ContactRateStudyResult zoh = runContactRateStudy(s);
    s.linear_model = true;
    const ContactRateStudyResult linear = runContactRateStudy(s);
    EXPECT_LT(linear.force_error_rel, 0.5 * zoh.force_error_rel) << rate << " Hz";
    EXPECT_LT(linear.force_error_rel, previous_linear) << rate << " Hz";
    previous_linear = linear.force_error_rel;
  }
  EXPECT_LT(previous_linear, 0.02);  // 500 Hz
}

TEST(ContactRateStudy, InvalidSettingsThrow) {
  ContactRateStudySettings s;
  s.update_rate_hz = 2000.0;  // faster than the loop
  EXPECT_THROW(runContactRateStudy(s), std::invalid_argument);
  s = ContactRateStudySettings{};
  s.tissue.normal_W = Eigen::Vector3d(0, 0, 2);
  EXPECT_THROW(runContactRateStudy(s), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::bench
