#include "surgical_sim/core/solve/symplectic_euler.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "solve_test_util.h"
#include "surgical_sim/core/solve/mechanical_energy.h"

namespace surgical_sim::core::test {
namespace {

using Law = SpringLatticeModel::Law;

/// Highest angular frequency sqrt(lambda_max(M^-1 K)) at rest [rad/s].
double maxAngularFrequency(const TissueModel& model) {
  Eigen::SparseMatrix<double> K = model.stiffnessPattern();
  model.assembleStiffness(model.restPositions(), TangentMode::Exact, K);
  const Eigen::VectorXd inv_sqrt_m = model.lumpedMass().cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled =
      inv_sqrt_m.asDiagonal() * Eigen::MatrixXd(K) * inv_sqrt_m.asDiagonal();
  return std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(scaled).eigenvalues().maxCoeff());
}

SimulationState randomlyMovingState(const TissueModel& model, unsigned seed) {
  SimulationState state = restState(model);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  for (Eigen::Index i = 0; i < state.x.size(); ++i) {
    state.x[i] += 0.002 * n(rng);
    state.v[i] = 0.1 * n(rng);
  }
  return state;
}

TEST(SymplecticEuler, SmallStepConservesEnergy) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(3, 3, 3, 0.05, 400.0, 0.02, Law::Nonlinear);
  DynamicsProblem problem = makeProblem(model, {});
  SimulationState state = randomlyMovingState(model, 1);
  const double dt = 0.03 * 2.0 / maxAngularFrequency(model);  // omega_max dt = 0.06
  SymplecticEuler integrator(1.0);
  const double initial = mechanicalEnergy(model, state.x, state.v, problem.external_force);
  double worst = 0.0;
  for (int step = 0; step < 2000; ++step) {
    const StepReport report = integrator.step(problem, dt, state);
    ASSERT_EQ(report.status, StepStatus::Ok);
    worst = std::max(worst, std::abs(report.energy - initial) / initial);
  }
  EXPECT_LT(worst, 0.03);
  EXPECT_NEAR(state.time, 2000 * dt, 1e-9);
}

TEST(SymplecticEuler, LargeStepIsDetectedAndStateRestored) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(3, 3, 3, 0.05, 400.0, 0.02, Law::Nonlinear);
  DynamicsProblem problem = makeProblem(model, dofsOfNodesAt(model, 2, 0.0));
  SimulationState state = randomlyMovingState(model, 2);
  for (const int d : problem.dirichlet.dofs) {
    state.x[d] = model.restPositions()[d];
    state.v[d] = 0.0;
  }
  const double dt = 10.0 * 2.0 / maxAngularFrequency(model);
  SymplecticEuler integrator(1.0);
  StepReport report;
  SimulationState before;
  int step = 0;
  for (; step < 100; ++step) {
    before = state;
    report = integrator.step(problem, dt, state);
    if (report.status != StepStatus::Ok) break;
  }
  ASSERT_LT(step, 100) << "instability not detected";
  EXPECT_TRUE(report.status == StepStatus::BlowUp || report.status == StepStatus::NonFinite)
      << toString(report.status);
  EXPECT_EQ(state.x, before.x);
  EXPECT_EQ(state.v, before.v);
  EXPECT_EQ(state.time, before.time);
  EXPECT_TRUE(state.x.allFinite());
}

TEST(SymplecticEuler, PrescribedMotionFromRestIsNotABlowUp) {
  // Energy enters through the moving boundary; the budget must account for it.
  SpringLatticeModel model =
      SpringLatticeModel::lattice(3, 3, 4, 0.05, 400.0, 0.02, Law::Nonlinear);
  DynamicsProblem problem = clampedUnderBodyForce(model, Eigen::Vector3d(0.0, 0.0, -9.81));
  SimulationState state = restState(model);
  const double dt = 0.2 * 2.0 / maxAngularFrequency(model);
  SymplecticEuler integrator(1.0);
  const Eigen::VectorXd base = problem.dirichlet.positions;
  for (int step = 1; step <= 3000; ++step) {
    for (Eigen::Index k = 0; k < base.size(); k += 3) {
      problem.dirichlet.positions[k] = base[k] + 0.02 * std::sin(20.0 * step * dt);
    }
    if (step == 1500) problem.external_force *= 3.0;  // load change between steps
    ASSERT_EQ(integrator.step(problem, dt, state).status, StepStatus::Ok) << "step " << step;
  }
  for (size_t k = 0; k < problem.dirichlet.dofs.size(); ++k) {
    EXPECT_EQ(state.x[problem.dirichlet.dofs[k]],
              problem.dirichlet.positions[static_cast<Eigen::Index>(k)]);
  }
}

TEST(SymplecticEuler, InvalidRatioThrowsNamingTheParameter) {
  expectInvalidArgumentNaming([] { SymplecticEuler integrator(0.0); },
                              "integrator.blow_up_energy_ratio");
}

}  // namespace
}  // namespace surgical_sim::core::test
