#include <gtest/gtest.h>

#include "robot_test_fixtures.h"
#include "surgical_sim/core/robot/continuum_robot_model.h"
#include "surgical_sim/core/robot/inverse_controller.h"
#include "surgical_sim/core/robot/section_compliances.h"

namespace surgical_sim::core {
namespace {

/// A target reached only by a feasible actuation far from rest: several iterations to converge.
Eigen::Vector3d farReachableTarget(ContinuumRobotModel& model) {
  Eigen::VectorXd lambda(4);
  lambda << 0.6, 0.3, 0.0, 0.1;
  model.solveEquilibrium(lambda, ModelSolveSettings{});
  const Eigen::Vector3d target = model.tipPosition();
  model.reset();
  return target;
}

TEST(InverseController, CancelCheckStopsTheSolveBetweenIterations) {
  const ContinuumRobotDescription d = test::smallCableRobot();
  ContinuumRobotModel model(d, computeSectionCompliances(d, ""));
  const Eigen::Vector3d target = farReachableTarget(model);
  InverseController c(model, InverseControllerSettings{});
  int checks = 0;
  c.setCancelCheck([&checks] { return ++checks > 1; });  // cancel before the second iteration
  const InverseResult r = c.solveTarget(target, 1e-7, 30);
  EXPECT_EQ(r.status, InverseStatus::Interrupted) << r.message;
  EXPECT_STREQ(toString(r.status), "interrupted");
  EXPECT_EQ(r.iterations, 1);
  EXPECT_EQ(checks, 2);
  EXPECT_GT(r.effector_error, 1e-7);
  EXPECT_EQ(r.actuation, c.actuation());  // the last iterate, not a stale or zero actuation
  EXPECT_GT(r.actuation.norm(), 0.0);

  c.setCancelCheck({});  // no check: the same solve now converges
  const InverseResult done = c.solveTarget(target, 1e-7, 30);
  EXPECT_EQ(done.status, InverseStatus::Converged) << done.message;
}

TEST(InverseController, CancelledBeforeTheFirstIterationLeavesTheRobotUnchanged) {
  const ContinuumRobotDescription d = test::smallCableRobot();
  ContinuumRobotModel model(d, computeSectionCompliances(d, ""));
  const Eigen::Vector3d target = farReachableTarget(model);
  InverseController c(model, InverseControllerSettings{});
  const Eigen::Vector3d tip = model.tipPosition();
  c.setCancelCheck([] { return true; });
  const InverseResult r = c.solveTarget(target, 1e-7, 30);
  EXPECT_EQ(r.status, InverseStatus::Interrupted);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ((model.tipPosition() - tip).norm(), 0.0);
}

}  // namespace
}  // namespace surgical_sim::core
