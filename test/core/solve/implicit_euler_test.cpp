#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "solve_test_util.h"
#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/solve/mechanical_energy.h"

namespace surgical_sim::core::test {
namespace {

using Law = SpringLatticeModel::Law;

std::unique_ptr<Integrator> integrator(const std::string& name, const char* solver = "cholmod") {
  IntegratorSettings settings;
  settings.relative_tolerance = 1e-12;
  PcgSettings pcg;
  pcg.relative_tolerance = 1e-14;
  return makeIntegrator(*enumFromName(kIntegratorNames, name), settings,
                        makeLinearSolver(*enumFromName(kSolverNames, solver), pcg));
}

class ImplicitScheme : public ::testing::TestWithParam<const char*> {};

// Backward Euler from rest under a constant force, linear model (f_int(x0) = 0):
//   (M + dt^2 K) v1 = dt f_ext,  x1 = x0 + dt v1.
TEST_P(ImplicitScheme, StepFromRestMatchesClosedForm) {
  SpringLatticeModel model = SpringLatticeModel::lattice(3, 2, 2, 0.05, 400.0, 0.02, Law::Linear);
  DynamicsProblem problem = makeProblem(model, {});
  problem.external_force = model.bodyForce(Eigen::Vector3d(1.0, -2.0, -9.81));
  problem.external_force[0] += 0.7;  // non-uniform: excites deformation, not only translation
  SimulationState state = restState(model);
  const double dt = 0.01;
  Eigen::SparseMatrix<double> K = model.stiffnessPattern();
  model.assembleStiffness(state.x, TangentMode::Exact, K);
  const Eigen::MatrixXd A =
      Eigen::MatrixXd(model.lumpedMass().asDiagonal()) + dt * dt * Eigen::MatrixXd(K);
  const Eigen::VectorXd v1 = A.llt().solve(dt * problem.external_force);
  const Eigen::VectorXd x1 = model.restPositions() + dt * v1;

  const StepReport report = integrator(GetParam())->step(problem, dt, state);
  ASSERT_EQ(report.status, StepStatus::Ok);
  EXPECT_LT((state.v - v1).norm(), 1e-10 * v1.norm());
  EXPECT_LT((state.x - x1).norm(), 1e-12 * x1.norm());
  EXPECT_DOUBLE_EQ(state.time, dt);
  EXPECT_NEAR(report.energy, mechanicalEnergy(model, state.x, state.v, problem.external_force),
              1e-12);
}

// The phases are disjoint parts of the step: each is timed, and together they take at most the
// step's wall time; a compliance solve after the step is counted and timed apart.
TEST_P(ImplicitScheme, PhaseTimesArePartsOfTheStepAndComplianceSolvesAreCounted) {
  SpringLatticeModel model = SpringLatticeModel::lattice(4, 3, 3, 0.05, 400.0, 0.02, Law::Linear);
  DynamicsProblem problem = makeProblem(model, dofsOfNodesAt(model, 2, 0.0));
  problem.external_force = model.bodyForce(Eigen::Vector3d(0.0, 0.0, -9.81));
  SimulationState state = restState(model);
  const std::unique_ptr<Integrator> scheme = integrator(GetParam());
  for (int k = 0; k < 3; ++k) {
    const Stopwatch watch;
    const StepReport report = scheme->step(problem, 0.01, state);
    const double step_seconds = watch.seconds();
    ASSERT_EQ(report.status, StepStatus::Ok);
    const StepPhaseTimes& p = report.phases;
    EXPECT_GT(p.forces, 0.0);
    EXPECT_GT(p.assembly, 0.0);
    EXPECT_GT(p.factorization, 0.0);
    EXPECT_GT(p.linear_solve, 0.0);
    EXPECT_LE(p.sum(), step_seconds);
  }
  const Integrator::ComplianceUse before = scheme->complianceUse();
  EXPECT_EQ(before.calls, 0);
  EXPECT_EQ(before.seconds, 0.0);
  Eigen::VectorXd dx;
  const Eigen::VectorXd f = Eigen::VectorXd::Ones(state.x.size());
  const Stopwatch watch;
  ASSERT_TRUE(scheme->applyStepCompliance(f, dx));
  ASSERT_TRUE(scheme->applyStepCompliance(f, dx));
  const double two_solves = watch.seconds();
  const Integrator::ComplianceUse after = scheme->complianceUse();
  EXPECT_EQ(after.calls, 2);
  EXPECT_GT(after.seconds, 0.0);
  EXPECT_LE(after.seconds, two_solves);
}

INSTANTIATE_TEST_SUITE_P(Schemes, ImplicitScheme,
                         ::testing::Values("implicit_euler_newton", "implicit_euler_linearized"));

TEST(ImplicitEulerNewton, EnergyDecaysWithoutDamping) {
  SpringLatticeModel model = SpringLatticeModel::lattice(3, 3, 3, 0.05, 400.0, 0.02, Law::Linear);
  DynamicsProblem problem = makeProblem(model, dofsOfNodesAt(model, 2, 0.0));
  SimulationState state = restState(model);
  for (int a = 0; a < model.numNodes(); ++a) {  // smooth bending shape, zero at the base
    const double z = model.restPositions()[3 * a + 2];
    state.x[3 * a] += 0.2 * z * z;
  }
  auto newton = integrator("implicit_euler_newton");
  double previous = mechanicalEnergy(model, state.x, state.v, problem.external_force);
  const double initial = previous;
  for (int step = 0; step < 300; ++step) {
    const StepReport report = newton->step(problem, 0.001, state);
    ASSERT_EQ(report.status, StepStatus::Ok);
    // Convex elastic energy: backward Euler dissipates monotonically.
    EXPECT_LE(report.energy, previous + 1e-12 * initial);
    previous = report.energy;
  }
  EXPECT_LT(previous, 0.9 * initial);  // numerically dissipative
}

TEST(ImplicitEulerNewton, NonlinearEnergyDecaysAndConverges) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(3, 3, 4, 0.05, 400.0, 0.02, Law::Nonlinear);
  DynamicsProblem problem = makeProblem(model, dofsOfNodesAt(model, 2, 0.0));
  SimulationState state = restState(model);
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 0.5);
  for (Eigen::Index i = 0; i < state.v.size(); ++i) state.v[i] = n(rng);
  for (const int d : problem.dirichlet.dofs) state.v[d] = 0.0;
  auto newton = integrator("implicit_euler_newton");
  const double initial = mechanicalEnergy(model, state.x, state.v, problem.external_force);
  double energy = initial;
  for (int step = 0; step < 100; ++step) {
    const StepReport report = newton->step(problem, 0.01, state);
    ASSERT_EQ(report.status, StepStatus::Ok);
    energy = report.energy;
  }
  EXPECT_LT(energy, 0.5 * initial);
}

// Forwards to a SpringLatticeModel and counts the force + stiffness evaluations, separate
// (addInternalForceAndStiffness) and with the energy (addInternalForceStiffnessAndEnergy).
class CountingModel final : public TissueModel {
 public:
  explicit CountingModel(const SpringLatticeModel& inner) : inner_(inner) {}
  std::string name() const override { return "counting"; }
  const Eigen::VectorXd& restPositions() const override { return inner_.restPositions(); }
  const Eigen::VectorXd& lumpedMass() const override { return inner_.lumpedMass(); }
  Eigen::VectorXd bodyForce(const Eigen::Vector3d& a) const override { return inner_.bodyForce(a); }
  double energy(const Eigen::VectorXd& x) const override { return inner_.energy(x); }
  void addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const override {
    inner_.addInternalForce(x, f);
  }
  const Eigen::SparseMatrix<double>& stiffnessPattern() const override {
    return inner_.stiffnessPattern();
  }
  void assembleStiffness(const Eigen::VectorXd& x, TangentMode mode,
                         Eigen::SparseMatrix<double>& K) const override {
    inner_.assembleStiffness(x, mode, K);
  }
  void addInternalForceAndStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd& f,
                                    Eigen::SparseMatrix<double>& K) const override {
    ++separate;
    inner_.addInternalForceAndStiffness(x, mode, f, K);
  }
  double addInternalForceStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode,
                                            Eigen::VectorXd& f,
                                            Eigen::SparseMatrix<double>& K) const override {
    ++with_energy;
    inner_.addInternalForceAndStiffness(x, mode, f, K);
    return inner_.energy(x);
  }
  void applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                      Eigen::VectorXd& y) const override {
    inner_.applyStiffness(x, mode, v, y);
  }
  mutable int separate = 0;
  mutable int with_energy = 0;

 private:
  const SpringLatticeModel& inner_;
};

// The linearized scheme evaluates the force and stiffness at the end of a step together with the
// energy and reuses them when the next step starts there; a state moved in between (a contact
// correction) gets a fresh evaluation, and so does the step after it (the prediction). Either way
// the trajectory equals steps that never reuse (reset before each step) to round-off.
TEST(ImplicitEulerLinearized, ReusesTheEndForceOnlyWhenTheStateWasNotMoved) {
  SpringLatticeModel lattice =
      SpringLatticeModel::lattice(3, 3, 4, 0.05, 400.0, 0.02, Law::Nonlinear);
  CountingModel model(lattice);
  DynamicsProblem problem = makeProblem(model, dofsOfNodesAt(model, 2, 0.0));
  problem.damping.mass_coefficient = 0.5;
  problem.damping.stiffness_coefficient = 0.01;
  problem.external_force = model.bodyForce(Eigen::Vector3d(0.0, 0.0, -9.81));
  SimulationState reusing = restState(model);
  SimulationState fresh = reusing;
  auto a = integrator("implicit_euler_linearized");
  auto b = integrator("implicit_euler_linearized");
  for (int step = 0; step < 40; ++step) {
    const bool moved = step >= 20 && step % 3 == 0;
    if (moved) {  // as a contact correction does between steps
      reusing.x[3 * model.numNodes() - 1] += 1e-4;
      fresh.x = reusing.x;
    }
    const int separate = model.separate;
    const int with_energy = model.with_energy;
    ASSERT_EQ(a->step(problem, 0.01, reusing).status, StepStatus::Ok);
    if (step >= 2) {
      // A moved step evaluates at its start and predicts a move before the next step too.
      const bool after_moved = step > 20 && (step - 1) % 3 == 0;
      EXPECT_EQ(model.separate - separate, moved || after_moved ? 1 : 0) << "step " << step;
      EXPECT_EQ(model.with_energy - with_energy, moved ? 0 : 1) << "step " << step;
    }
    b->reset();
    ASSERT_EQ(b->step(problem, 0.01, fresh).status, StepStatus::Ok);
    ASSERT_LT((reusing.x - fresh.x).norm(), 1e-12 * fresh.x.norm()) << "step " << step;
    ASSERT_LT((reusing.v - fresh.v).norm(), 1e-9 * (1.0 + fresh.v.norm())) << "step " << step;
  }
}

TEST(ImplicitEuler, LinearizedEqualsNewtonForLinearModel) {
  // Same backward Euler system: with a linear model one Newton step is exact. Includes Rayleigh
  // damping and a prescribed (moving) Dirichlet boundary.
  SpringLatticeModel model = SpringLatticeModel::lattice(3, 2, 3, 0.05, 400.0, 0.02, Law::Linear);
  DynamicsProblem problem = clampedUnderBodyForce(model, Eigen::Vector3d(0.0, 0.0, -9.81));
  problem.damping.mass_coefficient = 0.8;
  problem.damping.stiffness_coefficient = 0.002;
  SimulationState a = restState(model);
  SimulationState b = a;
  auto newton = integrator("implicit_euler_newton");
  auto linearized = integrator("implicit_euler_linearized");
  const Eigen::VectorXd base = problem.dirichlet.positions;
  for (int step = 1; step <= 20; ++step) {
    for (Eigen::Index k = 0; k < base.size(); k += 3) {
      problem.dirichlet.positions[k] = base[k] + 0.01 * std::sin(0.3 * step);  // shake in x
    }
    ASSERT_EQ(newton->step(problem, 0.01, a).status, StepStatus::Ok);
    ASSERT_EQ(linearized->step(problem, 0.01, b).status, StepStatus::Ok);
    EXPECT_LT((a.x - b.x).norm(), 1e-12 * a.x.norm());
    EXPECT_LT((a.v - b.v).norm(), 1e-9 * (1.0 + a.v.norm()));
  }
  for (size_t k = 0; k < problem.dirichlet.dofs.size(); ++k) {
    EXPECT_EQ(a.x[problem.dirichlet.dofs[k]],
              problem.dirichlet.positions[static_cast<Eigen::Index>(k)]);
  }
}

TEST(ImplicitEulerNewton, EverySolverGivesTheSameStep) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(3, 3, 3, 0.05, 400.0, 0.02, Law::Nonlinear);
  DynamicsProblem problem = clampedUnderBodyForce(model, Eigen::Vector3d(5.0, 0.0, -9.81));
  SimulationState reference = restState(model);
  auto cholmod = integrator("implicit_euler_newton");
  for (int k = 0; k < 5; ++k)
    ASSERT_EQ(cholmod->step(problem, 0.01, reference).status, StepStatus::Ok);
  for (const char* solver : {"pcg_jacobi", "pcg_block_jacobi", "pcg_ichol", "pcg_cholesky_reuse",
                             "pcg_cholesky_background", "pcg_cholesky_warped"}) {
    SimulationState state = restState(model);
    auto other = integrator("implicit_euler_newton", solver);
    for (int k = 0; k < 5; ++k) ASSERT_EQ(other->step(problem, 0.01, state).status, StepStatus::Ok);
    EXPECT_LT((state.x - reference.x).norm(), 1e-10 * reference.x.norm()) << solver;
  }
}

}  // namespace
}  // namespace surgical_sim::core::test
