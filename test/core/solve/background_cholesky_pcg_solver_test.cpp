#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cmath>
#include <limits>
#include <string>

#include "solve_test_util.h"
#include "surgical_sim/core/solve/background_cholesky_pcg_solver.h"
#include "surgical_sim/core/solve/cholmod_solver.h"
#include "surgical_sim/core/solve/pcg_solver.h"

namespace surgical_sim::core::test {
namespace {

using Law = SpringLatticeModel::Law;

constexpr int kSide = 10;  // lattice nodes per horizontal axis: 300 unknowns per layer

/// SPD matrix of a kSide x kSide x layers nonlinear spring lattice at pseudo-time t
/// (perturbedTangent).
Eigen::SparseMatrix<double> latticeMatrix(int layers, double t) {
  return perturbedTangent(
      SpringLatticeModel::lattice(kSide, kSide, layers, 0.1, 1000.0, 0.1, Law::Nonlinear), t);
}

/// The unknowns of `layers` full layers plus `extra` nodes of the next one (nodes are numbered
/// layer by layer): a principal submatrix of the (layers + 1)-layer matrix. More extra nodes
/// append unknowns coupled to the old ones, which keep their meaning and operator (as a cut
/// appends nodes).
Eigen::SparseMatrix<double> grownMatrix(int layers, int extra, double t) {
  const Eigen::SparseMatrix<double> full = latticeMatrix(layers + 1, t);
  const Eigen::Index n = 3 * (kSide * kSide * layers + extra);
  Eigen::SparseMatrix<double> A = full.topLeftCorner(n, n);
  A.makeCompressed();
  return A;
}

PcgSettings settings(int refresh_interval) {
  PcgSettings pcg;
  pcg.max_iterations = 1000;
  pcg.relative_tolerance = 1e-10;
  pcg.refresh_interval = refresh_interval;
  return pcg;
}

Eigen::VectorXd rightHandSide(Eigen::Index n) { return Eigen::VectorXd::LinSpaced(n, -1.0, 2.0); }

/// Direct solution of A x = b.
Eigen::VectorXd directSolve(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b) {
  CholmodSolver direct;
  direct.analyzePattern(A);
  EXPECT_TRUE(direct.factorize(A));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
  EXPECT_TRUE(direct.solve(b, x).ok);
  return x;
}

/// Solves A x = b from x = 0 (right away: the worker may still be busy) and expects the tolerance
/// and the direct solution.
void expectSolves(LinearSolver& solver, const Eigen::SparseMatrix<double>& A,
                  const std::string& context) {
  const Eigen::VectorXd b = rightHandSide(A.rows());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  const LinearSolveReport report = solver.solve(b, x);
  EXPECT_TRUE(report.ok) << context;
  EXPECT_GE(report.iterations, 1) << context;
  EXPECT_LE(report.relative_residual, 1e-10) << context;
  const Eigen::VectorXd expected = directSolve(A, b);
  EXPECT_LT((x - expected).norm(), 1e-8 * expected.norm()) << context;
}

TEST(BackgroundCholeskyPcgSolver, SolvesLikeCholeskyReuseAcrossSlowlyChangingMatrices) {
  // refresh_interval 2: a refresh is started every other call, so most factorize() and solve()
  // calls run while the worker factorizes (not asserted: the results must be right either way).
  BackgroundCholeskyPcgSolver background(settings(2));
  PcgSolver reuse(PcgPreconditioner::CholeskyReuse, settings(2));
  EXPECT_EQ(background.name(), "pcg_cholesky_background");
  const int layers = 4;
  background.analyzePattern(latticeMatrix(layers, 0.0));
  reuse.analyzePattern(latticeMatrix(layers, 0.0));
  for (int k = 0; k < 24; ++k) {
    const Eigen::SparseMatrix<double> A = latticeMatrix(layers, 0.03 * k);
    ASSERT_TRUE(background.factorize(A));
    ASSERT_TRUE(reuse.factorize(A));
    expectSolves(background, A, "background, call " + std::to_string(k));
    expectSolves(reuse, A, "reuse, call " + std::to_string(k));
  }
  // Only the first factorization ran on this thread.
  EXPECT_EQ(background.synchronousFactorizations(), 1);
  background.waitForRefresh();
  const Eigen::SparseMatrix<double> A = latticeMatrix(layers, 1.0);
  ASSERT_TRUE(background.factorize(A));
  EXPECT_GE(background.backgroundRefreshes(), 1);
  expectSolves(background, A, "after the wait");
}

TEST(BackgroundCholeskyPcgSolver, GrowingPatternNeedsNoSynchronousFactorization) {
  BackgroundCholeskyPcgSolver solver(settings(10));
  const Eigen::SparseMatrix<double> small = grownMatrix(5, 0, 0.0);
  solver.analyzePattern(small);
  ASSERT_TRUE(solver.factorize(small));
  expectSolves(solver, small, "before the change");
  ASSERT_EQ(solver.synchronousFactorizations(), 1);

  // Two nodes appended, coupled to the old ones: the solve runs with the old factor plus
  // block-Jacobi while the worker analyses and factorizes the new pattern.
  const Eigen::SparseMatrix<double> grown = grownMatrix(5, 2, 0.01);
  solver.analyzePattern(grown);
  ASSERT_TRUE(solver.factorize(grown));
  expectSolves(solver, grown, "interim preconditioner");
  EXPECT_EQ(solver.synchronousFactorizations(), 1);

  // The worker's factor of the new pattern is swapped in: exact for these values (in single
  // precision: two iterations reach the tolerance).
  solver.waitForRefresh();
  ASSERT_TRUE(solver.factorize(grown));
  EXPECT_EQ(solver.backgroundRefreshes(), 1);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(grown.rows());
  EXPECT_LE(solver.solve(rightHandSide(grown.rows()), x).iterations, 2);
  EXPECT_EQ(solver.synchronousFactorizations(), 1);
}

TEST(BackgroundCholeskyPcgSolver, PatternGrowingEveryCallLikeCuttingStaysAccurate) {
  // Two nodes appended at every call, never waiting for the worker: each solve uses whatever
  // factor of an earlier pattern has been delivered, plus block-Jacobi on the rest.
  BackgroundCholeskyPcgSolver solver(settings(10));
  for (int k = 0; k <= 8; ++k) {
    const Eigen::SparseMatrix<double> A = grownMatrix(5, 2 * k, 0.01 * k);
    solver.analyzePattern(A);
    ASSERT_TRUE(solver.factorize(A));
    expectSolves(solver, A, "growth " + std::to_string(k));
  }
  EXPECT_EQ(solver.synchronousFactorizations(), 1);
}

TEST(BackgroundCholeskyPcgSolver, NodeSplitLikeACutIsSolvedWithTheOldFactorInFewIterations) {
  // A crack through half of a mid-plane: its 25 nodes get copies holding the springs on the far
  // side, so the old factor is wrong there; the local correction solves that region exactly.
  const SpringLatticeModel lattice =
      SpringLatticeModel::lattice(kSide, kSide, 5, 0.1, 1000.0, 0.1, Law::Nonlinear);
  const Eigen::SparseMatrix<double> before = perturbedTangent(lattice, 0.0);
  const Eigen::SparseMatrix<double> after =
      perturbedTangent(crackedLattice(lattice, 0.4, 0.45), 0.01);
  ASSERT_EQ(after.rows(), before.rows() + 3 * 25);
  BackgroundCholeskyPcgSolver solver(settings(10));
  solver.analyzePattern(before);
  ASSERT_TRUE(solver.factorize(before));
  solver.analyzePattern(after);
  ASSERT_TRUE(solver.factorize(after));
  const Eigen::VectorXd b = rightHandSide(after.rows());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(after.rows());
  const LinearSolveReport report = solver.solve(b, x);
  EXPECT_TRUE(report.ok);
  EXPECT_LE(report.relative_residual, 1e-10);
  // Without the correction the old factor needs more than kFallbackIterations here (it then
  // refactorizes); with it, a handful.
  EXPECT_LE(report.iterations, 12);
  EXPECT_EQ(solver.synchronousFactorizations(), 1);
  const Eigen::VectorXd expected = directSolve(after, b);
  EXPECT_LT((x - expected).norm(), 1e-8 * expected.norm());
}

TEST(BackgroundCholeskyPcgSolver, FastChangingMatrixFallsBackAccuratelyAndBacksOff) {
  BackgroundCholeskyPcgSolver solver(settings(1000));  // no periodic refresh
  const Eigen::SparseMatrix<double> A = latticeMatrix(4, 0.0);
  // Same pattern, very different values: a factor of A is a poor preconditioner.
  Eigen::SparseMatrix<double> B = A;
  for (Eigen::Index i = 0; i < B.rows(); ++i) B.coeffRef(i, i) += 1e4 * (1.0 + std::sin(2.3 * i));
  solver.analyzePattern(A);
  ASSERT_TRUE(solver.factorize(A));
  ASSERT_EQ(solver.synchronousFactorizations(), 1);

  // The old factor fails within kFallbackIterations: fallback, then one synchronous call.
  ASSERT_TRUE(solver.factorize(B));
  expectSolves(solver, B, "fallback");
  EXPECT_EQ(solver.synchronousFactorizations(), 2);
  ASSERT_TRUE(solver.factorize(B));
  EXPECT_EQ(solver.synchronousFactorizations(), 3);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(B.rows());
  EXPECT_LE(solver.solve(rightHandSide(B.rows()), x).iterations, 2);  // B's own factor

  // Failing again right after: the back-off doubles to two synchronous calls.
  ASSERT_TRUE(solver.factorize(A));
  expectSolves(solver, A, "second fallback");
  EXPECT_EQ(solver.synchronousFactorizations(), 4);
  ASSERT_TRUE(solver.factorize(A));
  ASSERT_TRUE(solver.factorize(A));
  EXPECT_EQ(solver.synchronousFactorizations(), 6);

  // A small change succeeds with the old factor and ends the back-off.
  const Eigen::SparseMatrix<double> A1 = latticeMatrix(4, 0.01);
  ASSERT_TRUE(solver.factorize(A1));
  expectSolves(solver, A1, "old factor again");
  ASSERT_TRUE(solver.factorize(A1));
  EXPECT_EQ(solver.synchronousFactorizations(), 6);
}

TEST(BackgroundCholeskyPcgSolver, ShrinkingPatternFactorizesSynchronously) {
  BackgroundCholeskyPcgSolver solver(settings(10));
  const Eigen::SparseMatrix<double> large = grownMatrix(4, 2, 0.0);
  solver.analyzePattern(large);
  ASSERT_TRUE(solver.factorize(large));
  const Eigen::SparseMatrix<double> small = grownMatrix(4, 0, 0.0);
  solver.analyzePattern(small);
  ASSERT_TRUE(solver.factorize(small));
  EXPECT_EQ(solver.synchronousFactorizations(), 2);
  expectSolves(solver, small, "after shrinking");
  // The same pattern again keeps the factor.
  solver.analyzePattern(small);
  ASSERT_TRUE(solver.factorize(small));
  EXPECT_EQ(solver.synchronousFactorizations(), 2);
}

TEST(BackgroundCholeskyPcgSolver, NonSpdOrNonFiniteMatrixGivesAFailedReport) {
  BackgroundCholeskyPcgSolver solver(settings(1));  // every call hands its matrix to the worker
  const Eigen::SparseMatrix<double> A = latticeMatrix(3, 0.0);
  const Eigen::VectorXd b = rightHandSide(A.rows());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  solver.analyzePattern(A);

  // First call: no factor yet, the synchronous factorization fails.
  Eigen::SparseMatrix<double> indefinite = A;
  indefinite.coeffRef(5, 5) = -50.0;
  EXPECT_FALSE(solver.factorize(indefinite));
  EXPECT_FALSE(solver.solve(b, x).ok);

  ASSERT_TRUE(solver.factorize(A));
  expectSolves(solver, A, "SPD after indefinite");

  // With a factor of an SPD matrix: PCG breaks down, the fallback factorization fails, and the
  // worker's factorization of the same matrix fails too.
  const Eigen::SparseMatrix<double> negative = -A;
  if (solver.factorize(negative)) {
    x.setZero();
    EXPECT_FALSE(solver.solve(b, x).ok);
  }
  solver.waitForRefresh();

  Eigen::SparseMatrix<double> nan = A;
  nan.coeffRef(7, 7) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(solver.factorize(nan));
  x.setZero();
  EXPECT_FALSE(solver.solve(b, x).ok);

  ASSERT_TRUE(solver.factorize(A));
  expectSolves(solver, A, "SPD after NaN");
}

TEST(BackgroundCholeskyPcgSolver, DestructionWhileTheWorkerFactorizesIsSafe) {
  const Eigen::SparseMatrix<double> A = latticeMatrix(12, 0.0);
  for (int round = 0; round < 3; ++round) {
    BackgroundCholeskyPcgSolver solver(settings(1));
    solver.analyzePattern(A);
    ASSERT_TRUE(solver.factorize(A));
    ASSERT_TRUE(solver.factorize(A));  // hands A to the worker and returns
  }
  BackgroundCholeskyPcgSolver unused(settings(1));
}

TEST(BackgroundCholeskyPcgSolver, InvalidSettingsThrowNamingTheParameter) {
  PcgSettings pcg;
  pcg.refresh_interval = 0;
  expectInvalidArgumentNaming([&] { BackgroundCholeskyPcgSolver solver(pcg); },
                              "solver.refresh_interval");
}

}  // namespace
}  // namespace surgical_sim::core::test
