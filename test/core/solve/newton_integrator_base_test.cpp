#include <gtest/gtest.h>

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>

#include "solve_test_util.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/solve/conjugate_gradient.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::core::test {
namespace {

using Law = SpringLatticeModel::Law;

std::unique_ptr<Integrator> newton(const char* name, const IntegratorSettings& settings,
                                   SolverKind solver = SolverKind::Cholmod,
                                   const PcgSettings& pcg = {}) {
  return makeIntegrator(*enumFromName(kIntegratorNames, name), settings,
                        makeLinearSolver(solver, pcg));
}

class NewtonScheme : public ::testing::TestWithParam<const char*> {};

/// Free-DOF residual of the step from x0 with v0 = 0, no damping: f_int(x) + f_ext (quasi_static)
/// or M (x - x0) - dt^2 (f_int(x) + f_ext) (implicit_euler_newton).
double stepResidual(const std::string& scheme, const DynamicsProblem& problem, double dt,
                    const Eigen::VectorXd& x0, const Eigen::VectorXd& x) {
  Eigen::VectorXd r = problem.external_force;
  problem.model->addInternalForce(x, r);
  if (scheme == "implicit_euler_newton") {
    r = problem.model->lumpedMass().cwiseProduct(x - x0) - dt * dt * r;
  }
  for (const int d : problem.dirichlet.dofs) r[d] = 0.0;
  return r.norm();
}

// A step that starts at equilibrium has |r_0| at round-off: it converges by the round-off
// criterion without reducing |r| / |r_0| below the tolerance, and must still report a residual
// within the tolerance (the documented meaning of StepReport::residual).
TEST_P(NewtonScheme, RoundOffConvergedStepReportsResidualWithinTolerance) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(3, 3, 5, 0.01, 200.0, 1e-3, Law::Nonlinear);
  DynamicsProblem problem = clampedUnderBodyForce(model, Eigen::Vector3d(0.0, 0.0, -9.81));
  IntegratorSettings settings;
  SimulationState state = restState(model);
  ASSERT_EQ(newton("quasi_static", settings)->step(problem, 1.0, state).status, StepStatus::Ok);

  auto integrator = newton(GetParam(), settings);
  const double dt = 0.01;
  for (int step = 0; step < 3; ++step) {
    const Eigen::VectorXd x0 = state.x;
    const StepReport report = integrator->step(problem, dt, state);
    ASSERT_EQ(report.status, StepStatus::Ok);
    const double reduction = stepResidual(GetParam(), problem, dt, x0, state.x) /
                             stepResidual(GetParam(), problem, dt, x0, x0);
    EXPECT_GT(reduction, settings.relative_tolerance);  // converged by round-off
    EXPECT_LE(report.residual, settings.relative_tolerance);
  }
}

// Ok exactly when the reported residual is within the tolerance, along a loaded path.
TEST_P(NewtonScheme, StatusOkIffResidualWithinTolerance) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(2, 2, 6, 0.01, 200.0, 1e-3, Law::Nonlinear);
  DynamicsProblem problem = makeProblem(model, dofsOfNodesAt(model, 2, 0.0));
  IntegratorSettings settings;
  settings.max_iterations = 6;
  settings.max_load_step_levels = 0;
  auto integrator = newton(GetParam(), settings);
  SimulationState state = restState(model);
  int ok = 0;
  int not_converged = 0;
  for (int step = 1; step <= 12; ++step) {
    problem.external_force = model.bodyForce(Eigen::Vector3d(150.0 * step * step, 0.0, 0.0));
    const StepReport report = integrator->step(problem, 0.05, state);
    ASSERT_TRUE(report.status == StepStatus::Ok || report.status == StepStatus::NotConverged);
    EXPECT_EQ(report.status == StepStatus::Ok, report.residual <= settings.relative_tolerance)
        << "step " << step << " residual " << report.residual;
    (report.status == StepStatus::Ok ? ok : not_converged) += 1;
  }
  EXPECT_GT(ok, 0);
  EXPECT_GT(not_converged, 0);
}

INSTANTIATE_TEST_SUITE_P(Schemes, NewtonScheme,
                         ::testing::Values("implicit_euler_newton", "quasi_static"));

// Soft cantilever (E = 3 kPa, nu = 0.45, 3,075 DOFs) under self-weight, clamped at x = 0.
struct SoftBeam {
  std::unique_ptr<TissueModel> model;
  DynamicsProblem problem;
  SoftBeam() {
    const TetMesh mesh = makeBeam(0.1, 0.02, 0.02, Eigen::Vector3i(40, 4, 4), ElementType::Tet4);
    model = makeTissueModel(ModelKind::Corotational, mesh, Material::create(3e3, 0.45, 1000.0));
    problem = makeProblem(*model, dofsOfNodesAt(*model, 0, 0.0));
    problem.external_force = model->bodyForce(Eigen::Vector3d(0.0, -9.81, 0.0));
  }
};

PcgSettings scenePcg(std::optional<int> max_iterations) {
  PcgSettings pcg;
  pcg.relative_tolerance = 1e-6;  // the scene default
  pcg.max_iterations = max_iterations;
  return pcg;
}

TEST(NewtonIntegratorBase, SoftBeamStepsOkWithTheSizedPcgCap) {
  SoftBeam beam;
  const IntegratorSettings settings;
  auto integrator =
      newton("implicit_euler_newton", settings, SolverKind::PcgBlockJacobi, scenePcg(std::nullopt));
  SimulationState state = restState(*beam.model);
  for (int step = 1; step <= 3; ++step) {
    const StepReport report = integrator->step(beam.problem, 0.01, state);
    ASSERT_EQ(report.status, StepStatus::Ok) << "step " << step;
    EXPECT_LE(report.residual, settings.relative_tolerance);
  }
  EXPECT_LT(state.x[state.x.size() - 2], beam.model->restPositions()[state.x.size() - 2]);
}

TEST(NewtonIntegratorBase, CappedPcgDirectionGivesNotConvergedNotFailure) {
  SoftBeam beam;
  const IntegratorSettings settings;
  auto integrator =
      newton("implicit_euler_newton", settings, SolverKind::PcgBlockJacobi, scenePcg(3));
  SimulationState state = restState(*beam.model);
  const StepReport report = integrator->step(beam.problem, 0.01, state);
  EXPECT_EQ(report.status, StepStatus::NotConverged);
  EXPECT_GT(report.residual, settings.relative_tolerance);
  EXPECT_EQ(report.newton_iterations, settings.max_iterations);
  EXPECT_TRUE(state.x.allFinite());
  // The inexact directions still moved the beam down under its weight.
  EXPECT_LT(state.x[state.x.size() - 2], beam.model->restPositions()[state.x.size() - 2]);
}

TEST(PcgIterationCap, SizedFromTheProblemUnlessSet) {
  PcgSettings pcg;
  EXPECT_EQ(pcgIterationCap(pcg, 30), kMinSizedPcgIterations);
  EXPECT_EQ(pcgIterationCap(pcg, 5000), 5000);
  pcg.max_iterations = 7;
  EXPECT_EQ(pcgIterationCap(pcg, 5000), 7);
}

TEST(PcgIterationCap, CappedSolveIsMarkedCapped) {
  const Eigen::SparseMatrix<double> A = spdTestMatrix(3);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  PcgSettings pcg;
  pcg.max_iterations = 2;
  auto solver = makeLinearSolver(SolverKind::PcgJacobi, pcg);
  solver->analyzePattern(A);
  ASSERT_TRUE(solver->factorize(A));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  const LinearSolveReport capped = solver->solve(b, x);
  EXPECT_FALSE(capped.ok);
  EXPECT_TRUE(capped.capped);
  EXPECT_EQ(capped.iterations, 2);
  EXPECT_TRUE(x.allFinite());

  auto sized = makeLinearSolver(SolverKind::PcgJacobi, {});
  sized->analyzePattern(A);
  ASSERT_TRUE(sized->factorize(A));
  x.setZero();
  const LinearSolveReport solved = sized->solve(b, x);
  EXPECT_TRUE(solved.ok);
  EXPECT_FALSE(solved.capped);
}

}  // namespace
}  // namespace surgical_sim::core::test
