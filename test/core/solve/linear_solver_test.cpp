#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "solve_test_util.h"
#include "surgical_sim/core/solve/cholmod_solver.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/solve/pcg_solver.h"

namespace surgical_sim::core::test {
namespace {

const char* const kSolverNames[] = {"cholmod",
                                    "pcg_jacobi",
                                    "pcg_block_jacobi",
                                    "pcg_ichol",
                                    "pcg_cholesky_reuse",
                                    "pcg_cholesky_background",
                                    "pcg_cholesky_warped"};

PcgSettings tightPcg() {
  PcgSettings pcg;
  pcg.max_iterations = 2000;
  pcg.relative_tolerance = 1e-13;
  pcg.refresh_interval = 10;
  return pcg;
}

class EverySolver : public ::testing::TestWithParam<const char*> {};

TEST_P(EverySolver, MatchesDenseCholesky) {
  const Eigen::SparseMatrix<double> A = spdTestMatrix(1);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  const Eigen::VectorXd expected = Eigen::MatrixXd(A).llt().solve(b);
  std::unique_ptr<LinearSolver> solver =
      makeLinearSolver(*enumFromName(core::kSolverNames, GetParam()), tightPcg());
  EXPECT_EQ(solver->name(), GetParam());
  solver->analyzePattern(A);
  ASSERT_TRUE(solver->factorize(A));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  const LinearSolveReport report = solver->solve(b, x);
  EXPECT_TRUE(report.ok);
  EXPECT_GE(report.iterations, 1);
  EXPECT_LT(report.relative_residual, 1e-10);
  EXPECT_LT((x - expected).norm(), 1e-8 * expected.norm());
  // Second factorization with new values on the same pattern.
  const Eigen::SparseMatrix<double> A2 = spdTestMatrix(2);
  ASSERT_TRUE(solver->factorize(A2));
  solver->solve(b, x);
  EXPECT_LT((x - Eigen::MatrixXd(A2).llt().solve(b)).norm(), 1e-8 * x.norm());
}

INSTANTIATE_TEST_SUITE_P(LinearSolvers, EverySolver, ::testing::ValuesIn(kSolverNames));

TEST(CholmodSolver, FactorizeFailsOnIndefiniteMatrix) {
  Eigen::SparseMatrix<double> A = spdTestMatrix(3);
  CholmodSolver solver;
  solver.analyzePattern(A);
  ASSERT_TRUE(solver.factorize(A));
  A.coeffRef(5, 5) = -50.0;
  EXPECT_FALSE(solver.factorize(A));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  EXPECT_FALSE(solver.solve(Eigen::VectorXd::Ones(A.rows()), x).ok);
}

TEST(CholmodSolver, FactorizeFailsOnPatternChange) {
  const Eigen::SparseMatrix<double> A = spdTestMatrix(3);
  CholmodSolver solver;
  solver.analyzePattern(A);
  Eigen::SparseMatrix<double> diagonal(A.rows(), A.cols());
  diagonal.setIdentity();
  EXPECT_FALSE(solver.factorize(diagonal));
}

TEST(CholmodSolver, MetisOrderingSolvesLikeAmdWithASparserFactorIn3D) {
  // 12 x 12 x 12 spring lattice: a 3D mesh-like pattern where nested dissection fills less.
  const Eigen::SparseMatrix<double> A = perturbedTangent(
      SpringLatticeModel::lattice(12, 12, 12, 0.1, 1000.0, 0.1, SpringLatticeModel::Law::Nonlinear),
      0.0);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 1.0);
  CholmodSolver metis(CholmodOrdering::Metis), amd(CholmodOrdering::Amd);
  Eigen::VectorXd x_metis = Eigen::VectorXd::Zero(A.rows()), x_amd = x_metis;
  for (auto [solver, x] : {std::pair{&metis, &x_metis}, std::pair{&amd, &x_amd}}) {
    solver->analyzePattern(A);
    ASSERT_TRUE(solver->factorize(A));
    EXPECT_LT(solver->solve(b, *x).relative_residual, 1e-12);
  }
  EXPECT_LT((x_metis - x_amd).norm(), 1e-10 * x_amd.norm());
  EXPECT_GT(metis.factorNonzeros(), static_cast<double>(A.nonZeros()) / 2.0);
  EXPECT_LT(metis.factorNonzeros(), 0.9 * amd.factorNonzeros());
}

// 2D five-point operator on an n x n grid with edge conductances c(i, j) drawn from [1, contrast]
// (seeded), plus a small identity: SPD; another contrast field makes a poor preconditioner.
Eigen::SparseMatrix<double> gridOperator(int n, double contrast, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(1.0, contrast);
  std::vector<Eigen::Triplet<double>> t;
  const auto id = [n](int i, int j) { return i + n * j; };
  const auto link = [&](int a, int b) {
    const double c = u(rng);
    t.emplace_back(a, a, c);
    t.emplace_back(b, b, c);
    t.emplace_back(a, b, -c);
    t.emplace_back(b, a, -c);
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      t.emplace_back(id(i, j), id(i, j), 1e-2);
      if (i + 1 < n) link(id(i, j), id(i + 1, j));
      if (j + 1 < n) link(id(i, j), id(i, j + 1));
    }
  }
  Eigen::SparseMatrix<double> A(n * n, n * n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

// A plus a spring of stiffness c between nodes a and b for each pair, in each of the nodes'
// `dims` unknowns (node a's: dims a .. dims a + dims - 1): couplings A may not have.
Eigen::SparseMatrix<double> withLinks(const Eigen::SparseMatrix<double>& A,
                                      const std::vector<std::pair<int, int>>& pairs, int dims,
                                      double c) {
  std::vector<Eigen::Triplet<double>> t;
  for (const auto& [a, b] : pairs) {
    for (int k = 0; k < dims; ++k) {
      const int i = dims * a + k, j = dims * b + k;
      t.insert(t.end(), {{i, i, c}, {j, j, c}, {i, j, -c}, {j, i, -c}});
    }
  }
  Eigen::SparseMatrix<double> links(A.rows(), A.cols());
  links.setFromTriplets(t.begin(), t.end());
  Eigen::SparseMatrix<double> out = A + links;
  out.makeCompressed();
  return out;
}

// A 3D lattice tangent with a few couplings added (diagonal neighbours of a few nodes), as a cut
// adds them: the re-analysis keeps the ordering, solves as well and fills as little as a fresh one
// within kMaxKeptOrderingFill.
TEST(CholmodSolver, ReanalysisOfASmallPatternChangeKeepsTheOrdering) {
  const SpringLatticeModel lattice =
      SpringLatticeModel::lattice(8, 8, 8, 0.1, 1000.0, 0.1, SpringLatticeModel::Law::Nonlinear);
  const Eigen::SparseMatrix<double> A0 = perturbedTangent(lattice, 0.0);
  const Eigen::SparseMatrix<double> A1 =
      withLinks(A0, {{0, 9}, {100, 109}, {250, 259}, {400, 409}}, 3, 50.0);  // a to a + 1 + 8
  ASSERT_GT(A1.nonZeros(), A0.nonZeros());
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A0.rows(), -1.0, 1.0);
  CholmodSolver kept, fresh;
  kept.analyzePattern(A0);
  ASSERT_TRUE(kept.factorize(A0));
  kept.analyzeChangedPattern(A1);
  fresh.analyzePattern(A1);
  Eigen::VectorXd x_kept = Eigen::VectorXd::Zero(A1.rows()), x_fresh = x_kept;
  for (auto [solver, x] : {std::pair{&kept, &x_kept}, std::pair{&fresh, &x_fresh}}) {
    ASSERT_TRUE(solver->factorize(A1));
    EXPECT_LT(solver->solve(b, *x).relative_residual, 1e-12);
  }
  EXPECT_LT((x_kept - x_fresh).norm(), 1e-10 * x_fresh.norm());
  EXPECT_EQ(kept.orderings(), 1);
  EXPECT_LE(kept.factorNonzeros(), CholmodSolver::kMaxKeptOrderingFill * fresh.factorNonzeros());
}

// The pattern of a 30 x 30 grid with its nodes numbered at random, after a diagonal matrix: the
// diagonal's ordering fills the grid's factor many times over, so it is ordered afresh.
TEST(CholmodSolver, ReanalysisOrdersAfreshWhenTheKeptOrderingFillsTooMuch) {
  const Eigen::SparseMatrix<double> grid = gridOperator(30, 10.0, 1);
  Eigen::VectorXi order = Eigen::VectorXi::LinSpaced(grid.rows(), 0, grid.rows() - 1);
  std::shuffle(order.data(), order.data() + order.size(), std::mt19937(3));
  const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> scramble(order);
  Eigen::SparseMatrix<double> A1;
  A1 = grid.twistedBy(scramble);
  A1.makeCompressed();
  Eigen::SparseMatrix<double> A0(grid.rows(), grid.cols());
  A0.setIdentity();
  A0.makeCompressed();
  CholmodSolver solver, fresh;
  solver.analyzePattern(A0);
  solver.analyzeChangedPattern(A1);
  fresh.analyzePattern(A1);
  EXPECT_EQ(solver.orderings(), 2);
  EXPECT_EQ(solver.factorNonzeros(), fresh.factorNonzeros());
  ASSERT_TRUE(solver.factorize(A1));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A1.rows());
  EXPECT_LT(solver.solve(Eigen::VectorXd::Ones(A1.rows()), x).relative_residual, 1e-12);
}

TEST(PcgSolver, JacobiFailsOnNegativeDiagonal) {
  Eigen::SparseMatrix<double> A = spdTestMatrix(3);
  A.coeffRef(0, 0) = -1.0;
  PcgSolver solver(PcgPreconditioner::Jacobi, tightPcg());
  solver.analyzePattern(A);
  EXPECT_FALSE(solver.factorize(A));
}

TEST(PcgSolver, CholeskyReuseNeedsFewIterationsAfterSmallChange) {
  const Eigen::SparseMatrix<double> A0 = spdTestMatrix(4);
  // The same kind of change as between two time steps: a slightly different deformation.
  Eigen::SparseMatrix<double> A1 = A0;
  const Eigen::SparseMatrix<double> other = spdTestMatrix(5);
  A1 = 0.98 * A0 + 0.02 * other;
  A1.makeCompressed();
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(A0.rows());
  PcgSettings pcg;
  pcg.relative_tolerance = 1e-10;
  pcg.max_iterations = 1000;
  pcg.refresh_interval = 5;

  PcgSolver reuse(PcgPreconditioner::CholeskyReuse, pcg);
  reuse.analyzePattern(A0);
  ASSERT_TRUE(reuse.factorize(A0));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A0.rows());
  const int exact = reuse.solve(b, x).iterations;
  EXPECT_LE(exact, 2);               // exact factor, applied in single precision
  ASSERT_TRUE(reuse.factorize(A1));  // factor of A0 reused as preconditioner
  x.setZero();
  const LinearSolveReport reused = reuse.solve(b, x);
  EXPECT_TRUE(reused.ok);
  EXPECT_GT(reused.iterations, exact);
  EXPECT_LE(reused.iterations, 8);
  EXPECT_LT((x - Eigen::MatrixXd(A1).llt().solve(b)).norm(), 1e-8 * x.norm());

  PcgSolver jacobi(PcgPreconditioner::Jacobi, pcg);
  jacobi.analyzePattern(A1);
  ASSERT_TRUE(jacobi.factorize(A1));
  x.setZero();
  EXPECT_GT(jacobi.solve(b, x).iterations, 2 * reused.iterations);
}

TEST(PcgSolver, CholeskyReuseRefreshesAfterInterval) {
  const Eigen::SparseMatrix<double> A0 = spdTestMatrix(4);
  Eigen::SparseMatrix<double> A1 = 0.5 * A0 + 0.5 * spdTestMatrix(6);
  A1.makeCompressed();
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(A0.rows());
  PcgSettings pcg;
  pcg.refresh_interval = 2;
  PcgSolver solver(PcgPreconditioner::CholeskyReuse, pcg);
  solver.analyzePattern(A0);
  ASSERT_TRUE(solver.factorize(A0));  // call 1: factor of A0
  ASSERT_TRUE(solver.factorize(A1));  // call 2: reuse
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A0.rows());
  const int reused = solver.solve(b, x).iterations;
  ASSERT_TRUE(solver.factorize(A1));  // call 3: refresh -> exact factor of A1
  x.setZero();
  const int refreshed = solver.solve(b, x).iterations;
  EXPECT_LE(refreshed, 2);  // exact factor, applied in single precision
  EXPECT_GT(reused, refreshed);
}

// The kept factor of A0 needs hundreds of iterations on A1, far more than a refactorization costs:
// with adaptive_refresh the next factorize() refreshes it, then keeps the fresh factor; without,
// it is kept until refresh_interval. Every solve meets the tolerance either way.
TEST(PcgSolver, AdaptiveRefreshRefactorizesWhenTheKeptFactorCostsMoreThanARefresh) {
  const Eigen::SparseMatrix<double> A0 = gridOperator(60, 1.0, 1);
  const Eigen::SparseMatrix<double> A1 = gridOperator(60, 1e5, 2);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A0.rows(), -1.0, 2.0);
  CholmodSolver direct;
  direct.analyzePattern(A1);
  ASSERT_TRUE(direct.factorize(A1));
  Eigen::VectorXd expected(A1.rows());
  ASSERT_TRUE(direct.solve(b, expected).ok);
  for (const bool adaptive : {false, true}) {
    SCOPED_TRACE(adaptive ? "adaptive" : "interval");
    PcgSettings pcg;
    pcg.relative_tolerance = 1e-10;
    pcg.refresh_interval = 1000;
    pcg.adaptive_refresh = adaptive;
    PcgSolver solver(PcgPreconditioner::CholeskyReuse, pcg);
    solver.analyzePattern(A0);
    ASSERT_TRUE(solver.factorize(A0));
    Eigen::VectorXd x = Eigen::VectorXd::Zero(A0.rows());
    ASSERT_TRUE(solver.solve(b, x).ok);
    int stale_iterations = 0;
    for (int call = 0; call < 3; ++call) {
      ASSERT_TRUE(solver.factorize(A1));
      x.setZero();
      const LinearSolveReport report = solver.solve(b, x);
      ASSERT_TRUE(report.ok);
      EXPECT_LT((x - expected).norm(), 1e-7 * expected.norm());
      if (call == 0) stale_iterations = report.iterations;
      if (call > 0 && adaptive) {
        EXPECT_LE(report.iterations, 4);  // fresh factor, single precision
      }
    }
    EXPECT_GT(stale_iterations, 50);
    EXPECT_EQ(solver.choleskyFactorizations(), adaptive ? 2 : 1);
  }
}

// A kept factor of an older pattern (a few couplings added): the refresh re-analyses the new
// pattern with the kept ordering and factorizes it exactly.
TEST(PcgSolver, RefreshOfAChangedPatternKeepsTheOrdering) {
  const Eigen::SparseMatrix<double> A0 = gridOperator(30, 10.0, 1);
  // Node (i, j) to (i + 1, j + 1).
  const Eigen::SparseMatrix<double> A1 =
      withLinks(A0, {{31, 62}, {200, 231}, {451, 482}, {700, 731}}, 1, 5.0);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A0.rows(), -1.0, 2.0);
  const Eigen::VectorXd expected = Eigen::MatrixXd(A1).llt().solve(b);
  PcgSettings pcg;
  pcg.relative_tolerance = 1e-12;
  pcg.refresh_interval = 2;
  PcgSolver solver(PcgPreconditioner::CholeskyReuse, pcg);
  solver.analyzePattern(A0);
  ASSERT_TRUE(solver.factorize(A0));
  solver.analyzePattern(A1);  // the factor of A0 is kept, with a local correction
  for (int call = 0; call < 2; ++call) {
    ASSERT_TRUE(solver.factorize(A1));  // call 1: the refresh
    Eigen::VectorXd x = Eigen::VectorXd::Zero(A0.rows());
    const LinearSolveReport report = solver.solve(b, x);
    ASSERT_TRUE(report.ok);
    EXPECT_LT((x - expected).norm(), 1e-9 * expected.norm());
    if (call == 1) {
      EXPECT_LE(report.iterations, 3);  // exact factor, single precision
    }
  }
  EXPECT_EQ(solver.choleskyFactorizations(), 2);
  EXPECT_EQ(solver.choleskyAnalyses(), 2);
  EXPECT_EQ(solver.choleskyOrderings(), 1);
}

TEST(LinearSolverSettings, InvalidSettingsThrowNamingTheParameter) {
  PcgSettings pcg;
  pcg.relative_tolerance = -1e-8;
  expectInvalidArgumentNaming([&] { makeLinearSolver(SolverKind::PcgJacobi, pcg); },
                              "solver.relative_tolerance");
  pcg = PcgSettings();
  pcg.max_iterations = 0;
  expectInvalidArgumentNaming([&] { PcgSolver(PcgPreconditioner::Jacobi, pcg); },
                              "solver.max_iterations");
  pcg = PcgSettings();
  pcg.refresh_interval = 0;
  expectInvalidArgumentNaming([&] { validatePcgSettings(pcg); }, "solver.refresh_interval");
}

}  // namespace
}  // namespace surgical_sim::core::test
