#include <gtest/gtest.h>

#include <random>

#include "solve_test_util.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"

namespace surgical_sim::core::test {
namespace {

using Law = SpringLatticeModel::Law;

std::unique_ptr<Integrator> integrator(const std::string& name) {
  IntegratorSettings settings;
  settings.relative_tolerance = 1e-12;
  return makeIntegrator(
      *enumFromName(kIntegratorNames, name), settings,
      name == "symplectic_euler" ? nullptr : makeLinearSolver(SolverKind::Cholmod, {}));
}

/// Lattice fixed at z = 0, loaded by gravity-like body force, moving with a random velocity.
struct Fixture {
  explicit Fixture(Law law)
      : model(SpringLatticeModel::lattice(3, 3, 4, 0.01, 400.0, 2e-3, law)),
        problem(makeProblem(model, dofsOfNodesAt(model, 2, 0.0))),
        state(restState(model)) {
    problem.external_force = model.bodyForce(Eigen::Vector3d(5.0, -3.0, -20.0));
    problem.damping.mass_coefficient = 0.5;
    problem.damping.stiffness_coefficient = 1e-3;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (Eigen::Index i = 0; i < state.v.size(); ++i) state.v[i] = 0.01 * u(rng);
    for (const int d : problem.dirichlet.dofs) state.v[d] = 0.0;
    direction.setZero(state.x.size());
    for (Eigen::Index i = 0; i < direction.size(); ++i) direction[i] = u(rng);
  }
  SpringLatticeModel model;
  DynamicsProblem problem;
  SimulationState state;
  Eigen::VectorXd direction;  ///< extra force direction f [N]
};

/// Finite-difference check: dx vs (x(f_ext + eps f) - x(f_ext)) / eps from the same state.
void expectComplianceMatchesFiniteDifference(const std::string& name, Law law, double dt,
                                             double tolerance) {
  SCOPED_TRACE(name);
  Fixture fixture(law);
  auto base = integrator(name);
  auto perturbed = integrator(name);
  if (name == "quasi_static") fixture.state.v.setZero();

  SimulationState x_base = fixture.state;
  ASSERT_EQ(base->step(fixture.problem, dt, x_base).status, StepStatus::Ok);
  Eigen::VectorXd dx;
  ASSERT_TRUE(base->applyStepCompliance(fixture.direction, dx));

  const double eps = 1e-6;
  DynamicsProblem problem_eps = fixture.problem;
  problem_eps.external_force += eps * fixture.direction;
  SimulationState x_eps = fixture.state;
  ASSERT_EQ(perturbed->step(problem_eps, dt, x_eps).status, StepStatus::Ok);
  const Eigen::VectorXd finite_difference = (x_eps.x - x_base.x) / eps;

  ASSERT_GT(dx.norm(), 0.0);
  EXPECT_LT((dx - finite_difference).norm(), tolerance * dx.norm())
      << "dx " << dx.norm() << " fd " << finite_difference.norm();
  for (const int d : fixture.problem.dirichlet.dofs) EXPECT_EQ(dx[d], 0.0);

  // A second call reuses the factorization and gives the same answer.
  Eigen::VectorXd again;
  ASSERT_TRUE(base->applyStepCompliance(fixture.direction, again));
  EXPECT_LT((again - dx).norm(), 1e-12 * dx.norm());
}

TEST(StepCompliance, SymplecticEulerMatchesFiniteDifference) {
  expectComplianceMatchesFiniteDifference("symplectic_euler", Law::Linear, 1e-4, 1e-6);
  expectComplianceMatchesFiniteDifference("symplectic_euler", Law::Nonlinear, 1e-4, 1e-6);
}

TEST(StepCompliance, LinearizedImplicitEulerMatchesFiniteDifference) {
  expectComplianceMatchesFiniteDifference("implicit_euler_linearized", Law::Linear, 1e-2, 1e-6);
}

TEST(StepCompliance, NewtonImplicitEulerMatchesFiniteDifference) {
  expectComplianceMatchesFiniteDifference("implicit_euler_newton", Law::Linear, 1e-2, 1e-6);
  expectComplianceMatchesFiniteDifference("implicit_euler_newton", Law::Nonlinear, 1e-2, 1e-4);
}

TEST(StepCompliance, QuasiStaticMatchesFiniteDifference) {
  expectComplianceMatchesFiniteDifference("quasi_static", Law::Linear, 1.0, 1e-6);
  expectComplianceMatchesFiniteDifference("quasi_static", Law::Nonlinear, 1.0, 1e-4);
}

TEST(StepCompliance, SymplecticEulerIsDtSquaredOverMass) {
  Fixture fixture(Law::Linear);
  auto euler = integrator("symplectic_euler");
  const double dt = 1e-4;
  ASSERT_EQ(euler->step(fixture.problem, dt, fixture.state).status, StepStatus::Ok);
  Eigen::VectorXd dx;
  ASSERT_TRUE(euler->applyStepCompliance(fixture.direction, dx));
  const int free_dof = static_cast<int>(fixture.state.x.size()) - 1;  // top node, z
  EXPECT_NEAR(dx[free_dof], dt * dt * fixture.direction[free_dof] / 2e-3, 1e-18);
}

TEST(StepCompliance, UnavailableBeforeAStepAfterResetAndOnSizeMismatch) {
  for (const std::string name :
       {"symplectic_euler", "implicit_euler_linearized", "implicit_euler_newton", "quasi_static"}) {
    SCOPED_TRACE(name);
    Fixture fixture(Law::Linear);
    auto stepper = integrator(name);
    Eigen::VectorXd dx;
    EXPECT_FALSE(stepper->applyStepCompliance(fixture.direction, dx));
    ASSERT_NE(stepper->step(fixture.problem, 1e-3, fixture.state).status, StepStatus::SolverFailed);
    EXPECT_TRUE(stepper->applyStepCompliance(fixture.direction, dx));
    EXPECT_FALSE(stepper->applyStepCompliance(Eigen::VectorXd::Ones(3), dx));
    stepper->reset();
    EXPECT_FALSE(stepper->applyStepCompliance(fixture.direction, dx));
  }
}

TEST(StepCompliance, UnavailableAfterAFailedStep) {
  Fixture fixture(Law::Linear);
  auto stepper = integrator("implicit_euler_linearized");
  ASSERT_EQ(stepper->step(fixture.problem, 1e-3, fixture.state).status, StepStatus::Ok);
  Eigen::VectorXd dx;
  ASSERT_TRUE(stepper->applyStepCompliance(fixture.direction, dx));
  EXPECT_NE(stepper->step(fixture.problem, -1.0, fixture.state).status, StepStatus::Ok);
  EXPECT_FALSE(stepper->applyStepCompliance(fixture.direction, dx));
}

}  // namespace
}  // namespace surgical_sim::core::test
