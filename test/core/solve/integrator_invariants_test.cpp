// Cross-cutting properties of every integrator: momentum, damping, failure paths, factories.
#include <gtest/gtest.h>

#include <random>

#include "solve_test_util.h"
#include "surgical_sim/core/solve/dynamics_problem_check.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"

namespace surgical_sim::core::test {
namespace {

using Law = SpringLatticeModel::Law;

std::unique_ptr<Integrator> make(const std::string& name) {
  return makeIntegrator(*enumFromName(kIntegratorNames, name), IntegratorSettings(),
                        makeLinearSolver(SolverKind::Cholmod, {}));
}

SimulationState movingState(const TissueModel& model) {
  SimulationState state = restState(model);
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  for (Eigen::Index i = 0; i < state.x.size(); ++i) {
    state.x[i] += 0.003 * n(rng);
    state.v[i] = 0.2 * n(rng);
  }
  return state;
}

class MomentumConserving : public ::testing::TestWithParam<const char*> {};

TEST_P(MomentumConserving, FreeBodyKeepsLinearMomentum) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(3, 3, 3, 0.05, 400.0, 0.02, Law::Nonlinear);
  DynamicsProblem problem = makeProblem(model, {});
  SimulationState state = movingState(model);
  const Eigen::Vector3d p0 = momentum(model, state.v);
  const double scale = (model.lumpedMass().array() * state.v.array().abs()).sum();
  auto integrator = make(GetParam());
  for (int step = 0; step < 100; ++step) {
    ASSERT_EQ(integrator->step(problem, 0.002, state).status, StepStatus::Ok);
  }
  EXPECT_LT((momentum(model, state.v) - p0).norm(), 1e-12 * scale);
}

INSTANTIATE_TEST_SUITE_P(Integrators, MomentumConserving,
                         ::testing::Values("symplectic_euler", "implicit_euler_newton"));

/// Peak |x - rest| of the tip over the second half of a run [m].
double lateAmplitude(Integrator& integrator, const SpringLatticeModel& model,
                     const DynamicsProblem& problem, double dt, int steps) {
  SimulationState state = restState(model);
  for (int a = 0; a < model.numNodes(); ++a) {
    const double z = model.restPositions()[3 * a + 2];
    state.x[3 * a] += 0.3 * z * z;
  }
  double peak = 0.0;
  const Eigen::Index tip = state.x.size() - 3;
  for (int step = 0; step < steps; ++step) {
    EXPECT_EQ(integrator.step(problem, dt, state).status, StepStatus::Ok);
    if (step > steps / 2)
      peak = std::max(peak, std::abs(state.x[tip] - model.restPositions()[tip]));
  }
  return peak;
}

TEST(RayleighDamping, ReducesOscillationAmplitudeAndCostsNothingWhenZero) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(2, 2, 4, 0.05, 400.0, 0.02, Law::Nonlinear);
  DynamicsProblem problem = makeProblem(model, dofsOfNodesAt(model, 2, 0.0));
  const double dt = 5e-4;
  const int steps = 2000;
  for (const char* name : {"symplectic_euler", "implicit_euler_newton"}) {
    model.apply_calls = 0;
    model.stiffness_calls = 0;
    auto undamped_integrator = make(name);
    const double undamped = lateAmplitude(*undamped_integrator, model, problem, dt, steps);
    EXPECT_EQ(model.apply_calls, 0) << name;  // no damping work at all
    const int stiffness_calls_undamped = model.stiffness_calls;

    DynamicsProblem damped_problem = problem;
    damped_problem.damping.mass_coefficient = 2.0;
    damped_problem.damping.stiffness_coefficient = 1e-3;
    model.apply_calls = 0;
    model.stiffness_calls = 0;
    auto damped_integrator = make(name);
    const double damped = lateAmplitude(*damped_integrator, model, damped_problem, dt, steps);
    EXPECT_LT(damped, 0.5 * undamped) << name;
    if (std::string(name) == "symplectic_euler") {
      EXPECT_EQ(model.apply_calls, steps);  // beta K v, matrix-free
      EXPECT_EQ(stiffness_calls_undamped, 0);
    } else {
      EXPECT_GE(model.stiffness_calls, steps);  // + K(x_n) for the frozen damping
    }
  }
}

/// A 4-node chain fixed at its first node, pulled at its free end and moving: the set-up of the
/// failure tests; `before` is the state a failed step must leave.
struct MovingChain {
  MovingChain() {
    problem.external_force[9] = 1.0;
    state.v.setConstant(0.1);
    before = state;
  }
  SpringLatticeModel model = SpringLatticeModel::chain(4, 0.1, 100.0, 0.01, Law::Linear);
  DynamicsProblem problem = makeProblem(model, {0, 1, 2});
  SimulationState state = restState(model);
  SimulationState before;
};

class EveryIntegrator : public ::testing::TestWithParam<const char*> {};

TEST_P(EveryIntegrator, NonFiniteForcesRestoreTheState) {
  MovingChain c;
  c.model.poison_forces = true;
  const StepReport report = make(GetParam())->step(c.problem, 0.01, c.state);
  EXPECT_EQ(report.status, StepStatus::NonFinite) << toString(report.status);
  EXPECT_EQ(c.state.x, c.before.x);
  EXPECT_EQ(c.state.v, c.before.v);
  EXPECT_EQ(c.state.time, c.before.time);
}

TEST_P(EveryIntegrator, InconsistentProblemFailsWithoutThrowing) {
  SpringLatticeModel model = SpringLatticeModel::chain(4, 0.1, 100.0, 0.01, Law::Linear);
  DynamicsProblem problem = makeProblem(model, {0, 1, 2});
  problem.dirichlet.dofs.push_back(99);  // out of range, and no matching position
  SimulationState state = restState(model);
  const SimulationState before = state;
  StepReport report;
  EXPECT_NO_THROW(report = make(GetParam())->step(problem, 0.01, state));
  EXPECT_EQ(report.status, StepStatus::SolverFailed);
  EXPECT_EQ(state.x, before.x);
}

TEST_P(EveryIntegrator, NameMatchesFactoryKey) { EXPECT_EQ(make(GetParam())->name(), GetParam()); }

INSTANTIATE_TEST_SUITE_P(Integrators, EveryIntegrator,
                         ::testing::Values("symplectic_euler", "implicit_euler_linearized",
                                           "implicit_euler_newton", "quasi_static"));

class ImplicitIntegrator : public ::testing::TestWithParam<const char*> {};

TEST_P(ImplicitIntegrator, FailedLinearSolveRestoresTheState) {
  MovingChain c;
  auto integrator = makeIntegrator(*enumFromName(kIntegratorNames, GetParam()),
                                   IntegratorSettings(), std::make_unique<FailingLinearSolver>());
  const StepReport report = integrator->step(c.problem, 0.01, c.state);
  EXPECT_EQ(report.status, StepStatus::SolverFailed);
  EXPECT_EQ(c.state.x, c.before.x);
  EXPECT_EQ(c.state.v, c.before.v);
}

INSTANTIATE_TEST_SUITE_P(Integrators, ImplicitIntegrator,
                         ::testing::Values("implicit_euler_linearized", "implicit_euler_newton",
                                           "quasi_static"));

class NewtonIntegrator : public ::testing::TestWithParam<const char*> {};

TEST_P(NewtonIntegrator, IterationLimitGivesNotConvergedWithFiniteState) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(2, 2, 6, 0.01, 200.0, 1e-3, Law::Nonlinear);
  DynamicsProblem problem = clampedUnderBodyForce(model, Eigen::Vector3d(4000.0, 0.0, 0.0));
  IntegratorSettings settings;
  settings.max_iterations = 1;
  settings.max_load_step_levels = 0;
  auto integrator = makeIntegrator(*enumFromName(kIntegratorNames, GetParam()), settings,
                                   makeLinearSolver(SolverKind::Cholmod, {}));
  SimulationState state = restState(model);
  const StepReport report = integrator->step(problem, 0.05, state);
  EXPECT_EQ(report.status, StepStatus::NotConverged);
  EXPECT_EQ(report.newton_iterations, 1);
  EXPECT_GT(report.residual, settings.relative_tolerance);
  EXPECT_TRUE(state.x.allFinite());
  EXPECT_TRUE(state.v.allFinite());
}

INSTANTIATE_TEST_SUITE_P(Integrators, NewtonIntegrator,
                         ::testing::Values("implicit_euler_newton", "quasi_static"));

TEST(IntegratorSettings, InvalidSettingsThrowNamingTheParameter) {
  IntegratorSettings settings;
  settings.relative_tolerance = -1e-6;
  expectInvalidArgumentNaming([&] { validateIntegratorSettings(settings); },
                              "integrator.relative_tolerance");
  settings = IntegratorSettings();
  settings.max_iterations = 0;
  expectInvalidArgumentNaming(
      [&] {
        makeIntegrator(IntegratorKind::ImplicitEulerNewton, settings,
                       makeLinearSolver(SolverKind::Cholmod, {}));
      },
      "integrator.max_iterations");
  settings = IntegratorSettings();
  settings.max_load_step_levels = -1;
  expectInvalidArgumentNaming(
      [&] {
        makeIntegrator(IntegratorKind::QuasiStatic, settings,
                       makeLinearSolver(SolverKind::Cholmod, {}));
      },
      "integrator.max_load_step_levels");
  expectInvalidArgumentNaming(
      [] { makeIntegrator(IntegratorKind::ImplicitEulerNewton, IntegratorSettings(), nullptr); },
      "solver");
}

TEST(DynamicsProblemCheck, ValidatorNamesTheField) {
  SpringLatticeModel model = SpringLatticeModel::chain(3, 0.1, 100.0, 0.01, Law::Linear);
  DynamicsProblem problem = makeProblem(model, {0});
  SimulationState state = restState(model);
  EXPECT_NO_THROW(validateDynamicsProblem(problem, state));
  problem.damping.mass_coefficient = -1.0;
  expectInvalidArgumentNaming([&] { validateDynamicsProblem(problem, state); },
                              "problem.damping.mass_coefficient");
  problem.damping.mass_coefficient = 0.0;
  problem.external_force.resize(2);
  expectInvalidArgumentNaming([&] { validateDynamicsProblem(problem, state); },
                              "problem.external_force");
}

}  // namespace
}  // namespace surgical_sim::core::test
