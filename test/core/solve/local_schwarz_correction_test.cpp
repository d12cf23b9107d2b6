#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <algorithm>
#include <set>
#include <vector>

#include "solve_test_util.h"
#include "surgical_sim/core/solve/cholmod_solver.h"
#include "surgical_sim/core/solve/conjugate_gradient.h"
#include "surgical_sim/core/solve/local_schwarz_correction.h"

namespace surgical_sim::core::test {
namespace {

using Law = SpringLatticeModel::Law;

/// A 6 x 6 x 3 lattice before and after a crack through the nodes x = 0.2, y < 0.25 (9 nodes,
/// copies appended).
struct Crack {
  SpringLatticeModel lattice =
      SpringLatticeModel::lattice(6, 6, 3, 0.1, 1000.0, 0.1, Law::Nonlinear);
  SpringLatticeModel cracked = crackedLattice(lattice, 0.2, 0.25);
  Eigen::SparseMatrix<double> before = perturbedTangent(lattice, 0.0);
  Eigen::SparseMatrix<double> after = perturbedTangent(cracked, 0.05);
};

/// Node neighbours (sharing a nonzero block) of each node of A.
std::vector<std::set<int>> neighbours(const Eigen::SparseMatrix<double>& A) {
  std::vector<std::set<int>> out(static_cast<size_t>(A.cols() / 3));
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      out[static_cast<size_t>(j / 3)].insert(static_cast<int>(it.row() / 3));
    }
  }
  return out;
}

std::vector<int> unknownsOfNodes(const std::set<int>& nodes) {
  std::vector<int> unknowns;
  for (int a : nodes) {
    for (int c = 0; c < 3; ++c) unknowns.push_back(3 * a + c);
  }
  return unknowns;
}

/// The stale preconditioner G of a cut: the factor of `old` on its unknowns, the inverse diagonal
/// on the appended ones.
struct StaleFactor {
  explicit StaleFactor(const Eigen::SparseMatrix<double>& old, const Eigen::SparseMatrix<double>& A)
      : diagonal(A.diagonal()) {
    factor.analyzePattern(old);
    EXPECT_TRUE(factor.factorize(old));
    head_rhs.resize(old.rows());
    head.resize(old.rows());
  }
  bool operator()(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    head_rhs = r.head(head.size());
    if (!factor.solveWithFactor(head_rhs, head)) return false;
    z.head(head.size()) = head;
    const Eigen::Index tail = r.size() - head.size();
    z.tail(tail) = r.tail(tail).cwiseQuotient(diagonal.tail(tail));
    return true;
  }
  CholmodSolver factor;
  Eigen::VectorXd diagonal, head_rhs, head;
};

/// The crack with the stale preconditioner G of its matrix and G's local correction on `rings`
/// rings around the changed unknowns.
struct CorrectedCrack : Crack {
  explicit CorrectedCrack(int rings) : stale(before, after) {
    correction.setUnknowns(after, changedPatternUnknowns(after, before, rings));
    EXPECT_TRUE(correction.factorize(after));
  }
  StaleFactor stale;
  LocalSchwarzCorrection correction;
  const PreconditionerApply global = [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    return stale(r, z);
  };
  const PreconditionerApply corrected = [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    return correction.apply(after, r, z, global);
  };
};

TEST(ChangedPatternUnknowns, AreTheNodesWhoseNeighboursChangedAndTheirRings) {
  const Crack crack;
  const std::vector<std::set<int>> old_nodes = neighbours(crack.before);
  const std::vector<std::set<int>> new_nodes = neighbours(crack.after);
  std::set<int> changed;
  for (size_t a = 0; a < new_nodes.size(); ++a) {
    if (a >= old_nodes.size() || old_nodes[a] != new_nodes[a]) changed.insert(static_cast<int>(a));
  }
  // The 9 split nodes, their 9 copies and the far-side nodes that now couple to the copies.
  EXPECT_GT(changed.size(), 18u);
  EXPECT_EQ(changedPatternUnknowns(crack.after, crack.before, 0), unknownsOfNodes(changed));

  std::set<int> ring = changed;
  for (int a : changed)
    ring.insert(new_nodes[static_cast<size_t>(a)].begin(), new_nodes[static_cast<size_t>(a)].end());
  EXPECT_EQ(changedPatternUnknowns(crack.after, crack.before, 1), unknownsOfNodes(ring));

  EXPECT_TRUE(changedPatternUnknowns(crack.before, crack.before, 2).empty());
  const Eigen::SparseMatrix<double> later = perturbedTangent(crack.lattice, 1.0);
  EXPECT_TRUE(changedPatternUnknowns(later, crack.before, 2).empty()) << "values are not pattern";
}

TEST(LocalSchwarzCorrection, WithAnExactGlobalSolveItIsExact) {
  const Crack crack;
  const Eigen::SparseMatrix<double>& A = crack.after;
  CholmodSolver exact;
  exact.analyzePattern(A);
  ASSERT_TRUE(exact.factorize(A));
  LocalSchwarzCorrection correction;
  correction.setUnknowns(A, changedPatternUnknowns(A, crack.before, 1));
  ASSERT_TRUE(correction.active());
  ASSERT_TRUE(correction.factorize(A));
  const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 3.0);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(A.rows());
  ASSERT_TRUE(correction.apply(A, r, z, [&](const Eigen::VectorXd& s, Eigen::VectorXd& y) {
    return exact.solveWithFactor(s, y);
  }));
  EXPECT_LT((A * z - r).norm(), 1e-10 * r.norm());
}

TEST(LocalSchwarzCorrection, CorrectedStaleFactorIsSymmetricPositiveDefinite) {
  CorrectedCrack crack(1);
  const Eigen::SparseMatrix<double>& A = crack.after;
  std::srand(7);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd u = Eigen::VectorXd::Random(A.rows());
    const Eigen::VectorXd v = Eigen::VectorXd::Random(A.rows());
    Eigen::VectorXd Mu = Eigen::VectorXd::Zero(A.rows()), Mv = Mu;
    ASSERT_TRUE(crack.corrected(u, Mu));
    ASSERT_TRUE(crack.corrected(v, Mv));
    EXPECT_NEAR(v.dot(Mu), u.dot(Mv), 1e-10 * std::abs(u.dot(Mv)));
    EXPECT_GT(u.dot(Mu), 0.0);
  }
}

TEST(LocalSchwarzCorrection, PcgWithTheStaleFactorAfterACrackNeedsFarFewerIterations) {
  CorrectedCrack crack(2);
  const Eigen::SparseMatrix<double>& A = crack.after;
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  CgWorkspace work;
  work.resize(A.rows());
  Eigen::VectorXd x_stale = Eigen::VectorXd::Zero(A.rows()), x = x_stale;
  const LinearSolveReport plain =
      preconditionedConjugateGradient(A, b, x_stale, 1000, 1e-10, crack.global, work);
  const LinearSolveReport fixed =
      preconditionedConjugateGradient(A, b, x, 1000, 1e-10, crack.corrected, work);
  ASSERT_TRUE(plain.ok);
  ASSERT_TRUE(fixed.ok);
  EXPECT_LE(3 * fixed.iterations, plain.iterations)
      << "corrected " << fixed.iterations << ", stale factor alone " << plain.iterations;
  EXPECT_LT((A * x - b).norm(), 1e-10 * b.norm());
}

}  // namespace
}  // namespace surgical_sim::core::test
