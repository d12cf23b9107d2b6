#include "surgical_sim/core/solve/pcg_solver.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <memory>
#include <string>

#include "solve_test_util.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/solve/cholmod_solver.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/tissue/corotational_law.h"
#include "surgical_sim/core/tissue/efg_model.h"
#include "surgical_sim/core/tissue/fe_model.h"

namespace surgical_sim::core::test {
namespace {

constexpr double kTolerance = 1e-10;

Material beamMaterial() { return Material::create(1.0e4, 0.3, 1000.0); }
TetMesh beamMesh() { return makeBeam(0.2, 0.04, 0.04, {10, 2, 2}, ElementType::Tet4); }

FeModel corotationalBeam() {
  return FeModel(beamMesh(), beamMaterial(), std::make_unique<CorotationalLaw>(beamMaterial()));
}

EfgModel efgBeam() {
  EfgOptions options;
  options.spacing = 0.02;
  return EfgModel(beamMesh(), beamMaterial(), options);
}

PcgSettings settings(int refresh_interval) {
  PcgSettings pcg;
  pcg.relative_tolerance = kTolerance;
  pcg.refresh_interval = refresh_interval;
  return pcg;
}

/// Implicit-Euler-like system matrix M / dt^2 + K(x) (projected tangent), dt = 0.05 s.
Eigen::SparseMatrix<double> systemMatrix(const TissueModel& model, const Eigen::VectorXd& x) {
  Eigen::SparseMatrix<double> A = model.stiffnessPattern();
  model.assembleStiffness(x, TangentMode::ProjectedSpd, A);
  for (Eigen::Index i = 0; i < A.rows(); ++i) A.coeffRef(i, i) += model.lumpedMass()[i] / 0.0025;
  return A;
}

/// The beam bent (z += 0.05 (X / 0.2)^2) and rotated by 2 rad about a skew axis.
Eigen::VectorXd bentAndRotated(const TissueModel& model) {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(2.0, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  Eigen::VectorXd x = model.restPositions();
  for (int i = 0; i < model.numNodes(); ++i) {
    Eigen::Vector3d p = x.segment<3>(3 * i);
    p.z() += 0.05 * (p.x() / 0.2) * (p.x() / 0.2);
    x.segment<3>(3 * i) = R * p;
  }
  return x;
}

/// Factorizes at rest, then solves at the bent and rotated state with the rest factor; returns
/// the iterations and expects the direct solution.
int iterationsAfterRotation(LinearSolver& solver, const TissueModel& model) {
  const Eigen::VectorXd& rest = model.restPositions();
  const Eigen::SparseMatrix<double> A0 = systemMatrix(model, rest);
  solver.analyzePattern(A0);
  solver.setLinearizationState(model, rest);
  EXPECT_TRUE(solver.factorize(A0));
  const Eigen::VectorXd x = bentAndRotated(model);
  const Eigen::SparseMatrix<double> A = systemMatrix(model, x);
  solver.setLinearizationState(model, x);
  EXPECT_TRUE(solver.factorize(A));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  Eigen::VectorXd solution = Eigen::VectorXd::Zero(b.size());
  const LinearSolveReport report = solver.solve(b, solution);
  EXPECT_TRUE(report.ok) << solver.name() << " " << model.name();
  EXPECT_LE(report.relative_residual, kTolerance);
  CholmodSolver direct;
  direct.analyzePattern(A);
  EXPECT_TRUE(direct.factorize(A));
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(b.size());
  EXPECT_TRUE(direct.solve(b, expected).ok);
  EXPECT_LT((solution - expected).norm(), 1e-8 * expected.norm()) << solver.name();
  return report.iterations;
}

TEST(PcgCholeskyWarped, RestFactorAfterLargeRotationNeedsFewerIterationsThanPlainReuse) {
  const FeModel fe = corotationalBeam();
  const EfgModel efg = efgBeam();
  for (const TissueModel* model :
       {static_cast<const TissueModel*>(&fe), static_cast<const TissueModel*>(&efg)}) {
    PcgSolver warped(PcgPreconditioner::CholeskyWarped, settings(100));
    PcgSolver plain(PcgPreconditioner::CholeskyReuse, settings(100));
    const int warped_iterations = iterationsAfterRotation(warped, *model);
    const int plain_iterations = iterationsAfterRotation(plain, *model);
    EXPECT_EQ(warped.choleskyFactorizations(), 1);
    // Warping recovers most of what the rotation costs the plain factor.
    EXPECT_LT(2 * warped_iterations, plain_iterations) << model->name();
  }
}

TEST(PcgCholeskyWarped, WithoutRotationsActsAsTheReusedFactor) {
  const FeModel model = corotationalBeam();
  const Eigen::VectorXd x = bentAndRotated(model);
  const Eigen::SparseMatrix<double> A0 = systemMatrix(model, model.restPositions());
  const Eigen::SparseMatrix<double> A = systemMatrix(model, x);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  PcgSolver warped(PcgPreconditioner::CholeskyWarped, settings(100));
  PcgSolver plain(PcgPreconditioner::CholeskyReuse, settings(100));
  int iterations[2] = {0, 0};
  int k = 0;
  for (LinearSolver* solver :
       {static_cast<LinearSolver*>(&warped), static_cast<LinearSolver*>(&plain)}) {
    solver->analyzePattern(A0);
    ASSERT_TRUE(solver->factorize(A0));
    ASSERT_TRUE(solver->factorize(A));  // no setLinearizationState: no warp
    Eigen::VectorXd solution = Eigen::VectorXd::Zero(b.size());
    const LinearSolveReport report = solver->solve(b, solution);
    EXPECT_TRUE(report.ok);
    iterations[k++] = report.iterations;
  }
  EXPECT_EQ(iterations[0], iterations[1]);
}

TEST(PcgCholeskyWarped, RefactorizesEveryRefreshInterval) {
  const FeModel model = corotationalBeam();
  const Eigen::SparseMatrix<double> A = systemMatrix(model, model.restPositions());
  PcgSolver solver(PcgPreconditioner::CholeskyWarped, settings(3));
  solver.analyzePattern(A);
  for (int k = 0; k < 7; ++k) ASSERT_TRUE(solver.factorize(A));
  EXPECT_EQ(solver.choleskyFactorizations(), 3);  // calls 1, 4 and 7
}

// A free beam spinning about a skew axis (4 rad in 20 steps) with a bending initial velocity:
// the integrator announces each Newton state, and the steps match CHOLMOD's.
TEST(PcgCholeskyWarped, SpinningBeamStepsMatchCholmodWithFewerIterationsThanReuse) {
  const FeModel model = corotationalBeam();
  const DynamicsProblem problem = makeProblem(model, {});
  const Eigen::Vector3d omega = 20.0 * Eigen::Vector3d(0.2, 1.0, 0.4).normalized();  // [rad/s]
  SimulationState initial = restState(model);
  for (int i = 0; i < model.numNodes(); ++i) {
    const Eigen::Vector3d X = initial.x.segment<3>(3 * i);
    initial.v.segment<3>(3 * i) = omega.cross(X - Eigen::Vector3d(0.1, 0.0, 0.0));
    initial.v[3 * i + 2] += 0.5 * (X.x() - 0.1);
  }
  IntegratorSettings integrator_settings;
  integrator_settings.relative_tolerance = 1e-10;
  PcgSettings pcg = settings(1000);
  pcg.relative_tolerance = 1e-12;
  SimulationState reference = initial;
  auto cholmod = makeIntegrator(IntegratorKind::ImplicitEulerNewton, integrator_settings,
                                makeLinearSolver(SolverKind::Cholmod, pcg));
  for (int k = 0; k < 20; ++k) {
    ASSERT_EQ(cholmod->step(problem, 0.01, reference).status, StepStatus::Ok);
  }
  int iterations[2] = {0, 0};
  int s = 0;
  for (const SolverKind kind : {SolverKind::PcgCholeskyWarped, SolverKind::PcgCholeskyReuse}) {
    SimulationState state = initial;
    auto other = makeIntegrator(IntegratorKind::ImplicitEulerNewton, integrator_settings,
                                makeLinearSolver(kind, pcg));
    for (int k = 0; k < 20; ++k) {
      const StepReport report = other->step(problem, 0.01, state);
      ASSERT_EQ(report.status, StepStatus::Ok) << solverName(kind);
      iterations[s] += report.linear_iterations;
    }
    EXPECT_LT((state.x - reference.x).norm(), 1e-8 * reference.x.norm()) << solverName(kind);
    ++s;
  }
  EXPECT_LT(2 * iterations[0], iterations[1]);
}

}  // namespace
}  // namespace surgical_sim::core::test
