#include "surgical_sim/core/solve/single_precision_cholesky.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "solve_test_util.h"
#include "surgical_sim/core/solve/cholmod_solver.h"
#include "surgical_sim/core/solve/pcg_solver.h"

namespace surgical_sim::core::test {
namespace {

/// 8 x 8 x 8 nonlinear spring lattice tangent (1,536 unknowns): supernodes of several sizes and a
/// METIS ordering far from the identity.
Eigen::SparseMatrix<double> latticeMatrix() {
  return perturbedTangent(
      SpringLatticeModel::lattice(8, 8, 8, 0.1, 1000.0, 0.1, SpringLatticeModel::Law::Nonlinear),
      0.3);
}

Eigen::VectorXd rightHandSide(Eigen::Index n) {
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) b[i] = std::sin(0.37 * static_cast<double>(i)) + 0.1;
  return b;
}

/// The lattice matrix factorized by CHOLMOD, its single-precision copy and the double solution
/// of one right-hand side.
class CopiedFactor : public ::testing::Test {
 protected:
  void SetUp() override {
    cholmod.analyzePattern(A);
    ASSERT_TRUE(cholmod.factorize(A));
    ASSERT_TRUE(single.assign(cholmod));
    exact.setZero(A.rows());
    ASSERT_TRUE(cholmod.solveWithFactor(b, exact));
  }

  const Eigen::SparseMatrix<double> A = latticeMatrix();
  const Eigen::VectorXd b = rightHandSide(A.rows());
  CholmodSolver cholmod;
  SinglePrecisionCholesky single;
  Eigen::VectorXd exact, z;
};

TEST_F(CopiedFactor, SolvesLikeTheDoubleFactorToSinglePrecision) {
  EXPECT_TRUE(single.valid());
  EXPECT_EQ(single.rows(), A.rows());
  single.solve(b, z);
  ASSERT_EQ(z.size(), A.rows());
  // Single precision: float rounding of L and of the work vector (unit roundoff 6e-8) times a
  // modest condition number; a wrong ordering, supernode layout or transpose gives O(1) errors.
  EXPECT_LT((z - exact).norm() / exact.norm(), 1e-5);
  EXPECT_LT((b - A * z).norm() / b.norm(), 1e-5);
  // Reused work vectors: a second solve of another right-hand side is as accurate.
  const Eigen::VectorXd b2 = -2.0 * b.reverse();
  Eigen::VectorXd exact2 = Eigen::VectorXd::Zero(A.rows());
  ASSERT_TRUE(cholmod.solveWithFactor(b2, exact2));
  single.solve(b2, z);
  EXPECT_LT((z - exact2).norm() / exact2.norm(), 1e-5);
}

TEST_F(CopiedFactor, OneAndTwoThreadsGiveBitIdenticalSolutions) {
  SinglePrecisionCholesky one(1);
  SinglePrecisionCholesky two(2);
  ASSERT_TRUE(one.assign(cholmod));
  ASSERT_TRUE(two.assign(cholmod));
  Eigen::VectorXd z_one, z_two;
  for (const Eigen::VectorXd& rhs : {b, (-3.0 * b.reverse()).eval()}) {
    one.solve(rhs, z_one);
    two.solve(rhs, z_two);
    ASSERT_EQ(z_one.size(), A.rows());
    EXPECT_EQ(std::memcmp(z_one.data(), z_two.data(), sizeof(double) * z_one.size()), 0);
    EXPECT_LT((rhs - A * z_two).norm() / rhs.norm(), 1e-5);
  }
  EXPECT_THROW(SinglePrecisionCholesky(0), std::invalid_argument);
}

TEST_F(CopiedFactor, KeepsItsRelativeAccuracyForTinyHugeAndZeroRightHandSides) {
  for (const double factor : {1e-42, 1e-20, 1e30}) {  // 1e-42 r is subnormal in float
    single.solve(factor * b, z);
    EXPECT_LT((z - factor * exact).norm() / (factor * exact.norm()), 1e-5) << factor;
  }
  single.solve(Eigen::VectorXd::Zero(A.rows()), z);
  EXPECT_EQ(z, Eigen::VectorXd::Zero(A.rows()));
  Eigen::VectorXd nan = b;
  nan[7] = std::numeric_limits<double>::quiet_NaN();
  single.solve(nan, z);
  EXPECT_FALSE(z.allFinite());
}

TEST_F(CopiedFactor, StaysValidWhileTheSolverFactorizesAnotherMatrix) {
  const Eigen::SparseMatrix<double> B = 3.0 * A;
  ASSERT_TRUE(cholmod.factorize(B));  // the copy is of A, not of the solver's current factor
  single.solve(b, z);
  EXPECT_LT((z - exact).norm() / exact.norm(), 1e-5);
}

TEST(SinglePrecisionCholesky, RejectsASolverWithoutFactorAndValuesBeyondSinglePrecision) {
  const Eigen::SparseMatrix<double> A = latticeMatrix();
  CholmodSolver cholmod;
  SinglePrecisionCholesky single;
  EXPECT_FALSE(single.assign(cholmod));  // not analysed
  cholmod.analyzePattern(A);
  EXPECT_FALSE(single.assign(cholmod));  // analysed, not factorized
  EXPECT_FALSE(single.valid());
  EXPECT_EQ(single.rows(), 0);
  // L ~ sqrt(A): entries ~1e41, beyond float's 3.4e38.
  const Eigen::SparseMatrix<double> huge = 1e80 * A;
  ASSERT_TRUE(cholmod.factorize(huge));
  EXPECT_FALSE(single.assign(cholmod));
  EXPECT_FALSE(single.valid());
  // L ~ 1e-40: pivots below float's normal range.
  const Eigen::SparseMatrix<double> tiny = 1e-80 * A;
  ASSERT_TRUE(cholmod.factorize(tiny));
  EXPECT_FALSE(single.assign(cholmod));
  ASSERT_TRUE(cholmod.factorize(A));
  EXPECT_TRUE(single.assign(cholmod));
}

TEST(CholmodSolver, SinglePrecisionPreconditioningFallsBackToTheDoubleFactor) {
  const Eigen::SparseMatrix<double> A = 1e80 * latticeMatrix();
  CholmodSolver cholmod(CholmodOrdering::Metis, CholmodPreconditioning::SinglePrecision);
  cholmod.analyzePattern(A);
  ASSERT_TRUE(cholmod.factorize(A));
  const Eigen::VectorXd b = rightHandSide(A.rows());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  ASSERT_TRUE(cholmod.precondition(b, x));
  EXPECT_LT((b - A * x).norm() / b.norm(), 1e-12);  // the double factor: exact to rounding
}

TEST(CholmodSolver, SinglePrecisionPreconditioningIsAccurateToSinglePrecision) {
  const Eigen::SparseMatrix<double> A = latticeMatrix();
  CholmodSolver cholmod(CholmodOrdering::Metis, CholmodPreconditioning::SinglePrecision);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  const Eigen::VectorXd b = rightHandSide(A.rows());
  EXPECT_FALSE(cholmod.precondition(b, x));  // no factor yet
  cholmod.analyzePattern(A);
  ASSERT_TRUE(cholmod.factorize(A));
  ASSERT_TRUE(cholmod.precondition(b, x));
  const double residual = (b - A * x).norm() / b.norm();
  EXPECT_LT(residual, 1e-5);
  EXPECT_GT(residual, 1e-12);  // not the double factor
}

TEST(PcgSolver, CholeskyReuseWithTheSinglePrecisionFactorReachesTheDoubleTolerance) {
  const Eigen::SparseMatrix<double> A = latticeMatrix();
  PcgSettings settings;
  settings.relative_tolerance = 1e-12;
  PcgSolver pcg(PcgPreconditioner::CholeskyReuse, settings);
  pcg.analyzePattern(A);
  ASSERT_TRUE(pcg.factorize(A));
  const Eigen::VectorXd b = rightHandSide(A.rows());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  const LinearSolveReport report = pcg.solve(b, x);
  ASSERT_TRUE(report.ok);
  EXPECT_LE(report.relative_residual, 1e-12);
  EXPECT_LE(report.iterations, 4);  // each single-precision solve gains ~5 digits
  EXPECT_LT((b - A * x).norm() / b.norm(), 1e-11);
}

}  // namespace
}  // namespace surgical_sim::core::test
