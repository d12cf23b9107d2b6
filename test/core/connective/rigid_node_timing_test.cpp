// Time per linearized implicit Euler step of a rigid-node layer at Bosman's Table 4.4 sizes:
// the thread's CPU time, and the wall-time split per phase (relative figures: the machine is
// shared; nothing is asserted on time).

#include <gtest/gtest.h>

#include <cstdio>
#include <ctime>

#include "surgical_sim/core/connective/rigid_node_implicit_euler.h"
#include "surgical_sim/core/connective/rigid_node_sampling.h"

namespace surgical_sim::core {
namespace {

/// CPU time of the calling thread [s].
double threadSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// A nodes.x x nodes.y x nodes.z grid block (27 samples per cell, trilinear weights) of soft
/// tissue clamped at x = 0, sagging under gravity: steps 2..11 are timed, must be Ok and leave
/// the free end lower.
void timeGridBlock(const Eigen::Vector3i& nodes) {
  const Eigen::Vector3d size = 0.01 * (nodes - Eigen::Vector3i::Ones()).cast<double>();
  const RigidNodeLayout layout = trilinearGridLayout(Eigen::Vector3d::Zero(), size, nodes,
                                                     Material::create(20e3, 0.4, 1000.0));
  const RigidNodeModel model(layout.rest, layout.samples);
  RigidNodeProblem problem;
  problem.model = &model;
  problem.body_acceleration = Eigen::Vector3d(0, 0, -9.81);
  problem.mass_damping = 1.0;
  for (int i = 0; i < model.numNodes(); ++i)
    if (layout.rest.p_TN[i].x() == 0.0)
      for (int c = 0; c < kRigidNodeDofs; ++c) problem.fixed_dofs.push_back(kRigidNodeDofs * i + c);
  RigidNodeState state;
  state.configuration = layout.rest;
  state.velocity.setZero(model.numDofs());
  RigidNodeImplicitEuler integrator;
  ASSERT_EQ(integrator.step(problem, 0.01, state).status, StepStatus::Ok);
  const int steps = 10;
  StepPhaseTimes sum;
  const double cpu = threadSeconds();
  for (int i = 0; i < steps; ++i) {
    const StepReport report = integrator.step(problem, 0.01, state);
    ASSERT_EQ(report.status, StepStatus::Ok);
    sum.forces += report.phases.forces;
    sum.assembly += report.phases.assembly;
    sum.factorization += report.phases.factorization;
    sum.linear_solve += report.phases.linear_solve;
  }
  const double cpu_ms = 1e3 * (threadSeconds() - cpu) / steps;
  std::printf(
      "rigid nodes %d, samples %d: %.2f ms/step CPU; wall %.2f ms/step (sample loop %.2f, mass "
      "and A %.2f, factorization %.2f, solve %.2f ms)\n",
      model.numNodes(), model.numSamples(), cpu_ms, 1e3 * sum.sum() / steps,
      1e3 * sum.forces / steps, 1e3 * sum.assembly / steps, 1e3 * sum.factorization / steps,
      1e3 * sum.linear_solve / steps);
  // The free end sags under gravity.
  for (int i = 0; i < model.numNodes(); ++i) {
    if (layout.rest.p_TN[i].x() == size.x()) {
      EXPECT_LT(state.configuration.p_TN[i].z(), layout.rest.p_TN[i].z()) << "rigid node " << i;
    }
  }
}

TEST(RigidNodeTiming, ImplicitEulerStepAtBosmanTable44Sizes) {
  timeGridBlock(Eigen::Vector3i(4, 4, 3));  // 48 rigid nodes (Bosman: 648 samples)
  timeGridBlock(Eigen::Vector3i(6, 6, 6));  // 216 rigid nodes (Bosman: 3,000 samples)
}

}  // namespace
}  // namespace surgical_sim::core
