#include "surgical_sim/core/cutting/blade_sweep.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

namespace surgical_sim::core {
namespace {

/// Message of the std::invalid_argument validateBladePolyline throws, or "" if it accepts.
std::string polylineProblem(const Eigen::Matrix3Xd& blade) {
  try {
    validateBladePolyline("blade", blade);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

/// A straight blade of `points` points along x, 20 mm long [m].
Eigen::Matrix3Xd straightBlade(Eigen::Index points) {
  Eigen::Matrix3Xd blade = Eigen::Matrix3Xd::Zero(3, points);
  blade.row(0) = Eigen::RowVectorXd::LinSpaced(points, 0.0, 0.02);
  return blade;
}

TEST(BladeSweep, PolylineWithinLimitsIsAccepted) {
  EXPECT_EQ(polylineProblem(straightBlade(2)), "");
  EXPECT_EQ(polylineProblem(straightBlade(kMaxBladePoints)), "");
}

TEST(BladeSweep, PointCountOutsideTwoToMaxIsRejectedNamingThePolyline) {
  EXPECT_NE(polylineProblem(straightBlade(1)).find("blade has 1 points"), std::string::npos);
  const std::string too_many = polylineProblem(straightBlade(kMaxBladePoints + 1));
  EXPECT_NE(too_many.find("blade has 1001 points"), std::string::npos) << too_many;
  EXPECT_NE(too_many.find("at most 1000"), std::string::npos) << too_many;
}

TEST(BladeSweep, NonFiniteOrZeroLengthPolylineIsRejected) {
  Eigen::Matrix3Xd blade = straightBlade(3);
  blade(2, 1) = std::numeric_limits<double>::infinity();
  EXPECT_NE(polylineProblem(blade).find("blade is not finite"), std::string::npos);
  const Eigen::Matrix3Xd coincident = Eigen::Vector3d(0.01, 0.0, 0.0).replicate(1, 4);
  EXPECT_NE(polylineProblem(coincident).find("total length of 0 m"), std::string::npos);
  Eigen::Matrix3Xd tiny = coincident;
  tiny(0, 3) += 0.5 * kMinBladeLength;
  EXPECT_NE(polylineProblem(tiny).find("must not all coincide"), std::string::npos);
}

TEST(BladeSweep, SweepChecksBothPolylinesAndTheirShapes) {
  BladeSweep sweep{straightBlade(3), straightBlade(3)};
  EXPECT_NO_THROW(validateBladeSweep(sweep));
  sweep.end = straightBlade(4);
  EXPECT_THROW(validateBladeSweep(sweep), std::invalid_argument);
  sweep.end = Eigen::Matrix3Xd::Zero(3, 3);
  try {
    validateBladeSweep(sweep);
    FAIL() << "a zero-length end polyline was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("blade_sweep.end"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace surgical_sim::core
