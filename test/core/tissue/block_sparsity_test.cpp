#include "surgical_sim/core/tissue/block_sparsity.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

/// Reference pattern: every 3 x 3 block of every pair of nodes in a group, through triplets.
Eigen::SparseMatrix<double> tripletPattern(int num_nodes, const Eigen::MatrixXi& groups) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (Eigen::Index g = 0; g < groups.cols(); ++g)
    for (Eigen::Index a = 0; a < groups.rows(); ++a)
      for (Eigen::Index b = 0; b < groups.rows(); ++b)
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            triplets.emplace_back(3 * groups(b, g) + r, 3 * groups(a, g) + c, 0.0);
  Eigen::SparseMatrix<double> pattern(3 * num_nodes, 3 * num_nodes);
  pattern.setFromTriplets(triplets.begin(), triplets.end());
  pattern.makeCompressed();
  return pattern;
}

void expectSameStructure(const Eigen::SparseMatrix<double>& a,
                         const Eigen::SparseMatrix<double>& b) {
  ASSERT_TRUE(a.isCompressed());
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.cols(), b.cols());
  ASSERT_EQ(a.nonZeros(), b.nonZeros());
  for (Eigen::Index j = 0; j <= a.cols(); ++j) {
    ASSERT_EQ(a.outerIndexPtr()[j], b.outerIndexPtr()[j]) << "column " << j;
  }
  for (Eigen::Index p = 0; p < a.nonZeros(); ++p) {
    ASSERT_EQ(a.innerIndexPtr()[p], b.innerIndexPtr()[p]) << "entry " << p;
    ASSERT_EQ(a.valuePtr()[p], 0.0);
  }
}

/// Scatter-adds a random dense matrix per group through the map and compares with the dense sum
/// of the same matrices placed at the groups' dofs.
void expectScatterAssemblesGroupMatrices(int num_nodes, const Eigen::MatrixXi& groups) {
  const Eigen::SparseMatrix<double> pattern = makeBlockPattern(num_nodes, groups);
  const std::vector<int> map = makeScatterMap(pattern, groups);
  const auto dofs = static_cast<int>(3 * groups.rows());
  ASSERT_EQ(map.size(), static_cast<size_t>(groups.cols() * dofs * dofs));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::SparseMatrix<double> assembled = pattern;
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * num_nodes, 3 * num_nodes);
  for (Eigen::Index g = 0; g < groups.cols(); ++g) {
    Eigen::MatrixXd Ke(dofs, dofs);
    for (Eigen::Index i = 0; i < Ke.size(); ++i) Ke.data()[i] = u(rng);
    for (int i = 0; i < dofs * dofs; ++i) {
      assembled.valuePtr()[map[static_cast<size_t>(g * dofs * dofs + i)]] += Ke.data()[i];
    }
    for (int c = 0; c < dofs; ++c)
      for (int r = 0; r < dofs; ++r)
        dense(3 * groups(r / 3, g) + r % 3, 3 * groups(c / 3, g) + c % 3) += Ke(r, c);
  }
  EXPECT_LT((Eigen::MatrixXd(assembled) - dense).lpNorm<Eigen::Infinity>(), 1e-12);
}

TEST(BlockSparsity, TetMeshPatternHasTheBlocksOfEveryElement) {
  std::mt19937 rng(11);
  const TetMesh mesh = test::jitteredLattice(3, 1.0, 0.1, rng);
  expectSameStructure(makeBlockPattern(mesh.numNodes(), mesh.elements),
                      tripletPattern(mesh.numNodes(), mesh.elements));
  expectScatterAssemblesGroupMatrices(mesh.numNodes(), mesh.elements);
}

TEST(BlockSparsity, SpringsAndIsolatedNodes) {
  // Two-node groups (springs), a spring listed twice, and nodes 5, 6 in no group.
  Eigen::MatrixXi springs(2, 5);
  springs << 0, 1, 2, 4, 1, 1, 2, 3, 0, 2;
  expectSameStructure(makeBlockPattern(7, springs), tripletPattern(7, springs));
  expectScatterAssemblesGroupMatrices(7, springs);
}

}  // namespace
}  // namespace surgical_sim::core
