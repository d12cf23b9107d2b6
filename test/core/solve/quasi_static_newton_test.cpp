#include "surgical_sim/core/solve/quasi_static_newton.h"

#include <gtest/gtest.h>

#include "solve_test_util.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"

namespace surgical_sim::core::test {
namespace {

using Law = SpringLatticeModel::Law;

std::unique_ptr<Integrator> quasiStatic(const IntegratorSettings& settings = {}) {
  return makeIntegrator(IntegratorKind::QuasiStatic, settings,
                        makeLinearSolver(SolverKind::Cholmod, {}));
}

/// Free-DOF equilibrium residual |f_int + f_ext| relative to |f_ext|.
double relativeImbalance(const TissueModel& model, const DynamicsProblem& problem,
                         const Eigen::VectorXd& x) {
  Eigen::VectorXd f = problem.external_force;
  model.addInternalForce(x, f);
  for (const int d : problem.dirichlet.dofs) f[d] = 0.0;
  return f.norm() / problem.external_force.norm();
}

TEST(QuasiStaticNewton, LinearChainEndLoadGivesSeriesSpringDisplacement) {
  // n springs in series, k each, end force F: node a moves a F / k.
  const int nodes = 6;
  const double k = 250.0, force = 3.0;
  SpringLatticeModel model = SpringLatticeModel::chain(nodes, 0.1, k, 0.01, Law::Linear);
  DynamicsProblem problem = makeProblem(model, {0, 1, 2});
  problem.external_force[3 * (nodes - 1)] = force;
  SimulationState state = restState(model);
  const StepReport report = quasiStatic()->step(problem, 1.0, state);
  ASSERT_EQ(report.status, StepStatus::Ok);
  for (int a = 0; a < nodes; ++a) {
    EXPECT_NEAR(state.x[3 * a] - model.restPositions()[3 * a], a * force / k, 1e-12);
    EXPECT_NEAR(state.x[3 * a + 1], 0.0, 1e-12);
  }
  EXPECT_EQ(state.v, Eigen::VectorXd::Zero(state.v.size()));
  EXPECT_LE(report.newton_iterations, 2);  // linear problem: one Newton step
}

TEST(QuasiStaticNewton, NonlinearAxialChainMatchesPenAndPaper) {
  // A geometrically exact spring under axial tension F stretches by F / k.
  const int nodes = 5;
  const double k = 100.0, force = 40.0;  // 40 % strain per spring: strongly nonlinear tangent
  SpringLatticeModel model = SpringLatticeModel::chain(nodes, 0.1, k, 0.01, Law::Nonlinear);
  std::vector<int> fixed = {0, 1, 2};
  for (int a = 1; a < nodes; ++a) {
    fixed.push_back(3 * a + 1);
    fixed.push_back(3 * a + 2);
  }
  DynamicsProblem problem = makeProblem(model, fixed);
  problem.external_force[3 * (nodes - 1)] = force;
  SimulationState state = restState(model);
  const StepReport report = quasiStatic()->step(problem, 1.0, state);
  ASSERT_EQ(report.status, StepStatus::Ok);
  EXPECT_NEAR(state.x[3 * (nodes - 1)] - 0.4, (nodes - 1) * force / k, 1e-9);
  EXPECT_LT(relativeImbalance(model, problem, state.x), 1e-8);
}

TEST(QuasiStaticNewton, NonlinearLatticeConverges) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(3, 3, 5, 0.01, 200.0, 1e-3, Law::Nonlinear);
  DynamicsProblem problem =
      clampedUnderBodyForce(model, Eigen::Vector3d(300.0, 0.0, -500.0));  // large sag
  SimulationState state = restState(model);
  IntegratorSettings settings;
  settings.relative_tolerance = 1e-10;
  const StepReport report = quasiStatic(settings)->step(problem, 1.0, state);
  ASSERT_EQ(report.status, StepStatus::Ok);
  EXPECT_LT(report.residual, 1e-10);
  EXPECT_GT(report.newton_iterations, 1);
  EXPECT_LT(relativeImbalance(model, problem, state.x), 1e-8);
  const double tip_drop = model.restPositions()[state.x.size() - 1] - state.x[state.x.size() - 1];
  EXPECT_GT(tip_drop, 1e-3);  // the load really deformed the lattice
}

TEST(QuasiStaticNewton, PrescribedEndDisplacementStretchesChainUniformly) {
  const int nodes = 5;
  SpringLatticeModel model = SpringLatticeModel::chain(nodes, 0.1, 50.0, 0.01, Law::Linear);
  DynamicsProblem problem = makeProblem(model, {0, 1, 2, 3 * (nodes - 1)});
  problem.dirichlet.positions[3] = 0.4 + 0.08;  // pull the end by 8 cm
  SimulationState state = restState(model);
  ASSERT_EQ(quasiStatic()->step(problem, 1.0, state).status, StepStatus::Ok);
  for (int a = 0; a < nodes; ++a) EXPECT_NEAR(state.x[3 * a], a * 0.12, 1e-12);
}

TEST(QuasiStaticNewton, LoadSteppingRescuesAHardSolve) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(2, 2, 6, 0.01, 200.0, 1e-3, Law::Nonlinear);
  DynamicsProblem problem = makeProblem(model, dofsOfNodesAt(model, 2, 0.0));
  // Slender column under a lateral load: large rotations, the tip moves more than the width.
  problem.external_force = model.bodyForce(Eigen::Vector3d(4000.0, 0.0, 0.0));
  IntegratorSettings settings;
  settings.max_iterations = 8;  // too few for the full load at once
  settings.max_load_step_levels = 0;
  SimulationState state = restState(model);
  const StepReport single = quasiStatic(settings)->step(problem, 1.0, state);
  ASSERT_EQ(single.status, StepStatus::NotConverged);
  EXPECT_TRUE(state.x.allFinite());

  settings.max_load_step_levels = 6;
  state = restState(model);
  const StepReport stepped = quasiStatic(settings)->step(problem, 1.0, state);
  EXPECT_EQ(stepped.status, StepStatus::Ok);
  EXPECT_GT(stepped.newton_iterations, settings.max_iterations);
  EXPECT_LT(relativeImbalance(model, problem, state.x), 1e-7);
  const Eigen::Index tip = state.x.size() - 3;
  EXPECT_GT(state.x[tip] - model.restPositions()[tip], 0.02);  // tip moved more than 2 widths
}

TEST(QuasiStaticNewton, SingularProblemFailsAndRestoresState) {
  SpringLatticeModel model = SpringLatticeModel::chain(3, 0.1, 50.0, 0.01, Law::Linear);
  DynamicsProblem problem = makeProblem(model, {});  // rigid modes free: K singular
  problem.external_force[0] = 1.0;
  SimulationState state = restState(model);
  state.v.setConstant(0.5);
  const SimulationState before = state;
  const StepReport report = quasiStatic()->step(problem, 1.0, state);
  EXPECT_NE(report.status, StepStatus::Ok);
  if (report.status == StepStatus::SolverFailed || report.status == StepStatus::NonFinite) {
    EXPECT_EQ(state.x, before.x);
    EXPECT_EQ(state.v, before.v);
  }
  EXPECT_TRUE(state.x.allFinite());
}

}  // namespace
}  // namespace surgical_sim::core::test
