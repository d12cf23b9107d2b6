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

/// The same groups with an extra node `isolated` (in no group): node indices >= isolated shift by
/// one, so the pattern gets empty columns and rows in the middle.
Eigen::MatrixXi withIsolatedNode(const Eigen::MatrixXi& groups, int isolated) {
  return groups.unaryExpr([isolated](int i) { return i < isolated ? i : i + 1; });
}

/// Checks makeBlockPattern() against tripletPattern(), then scatter-adds a random dense matrix per
/// group through BlockScatterMap and compares exactly with the dense sum of the same matrices
/// placed at the groups' dofs (each entry receives the same contributions in the same group order,
/// so the sums are bit-identical).
template <int Size>
void expectScatterAssemblesGroupMatrices(int num_nodes, const Eigen::MatrixXi& groups) {
  ASSERT_EQ(3 * groups.rows(), Size);
  const Eigen::SparseMatrix<double> pattern = makeBlockPattern(num_nodes, groups);
  expectSameStructure(pattern, tripletPattern(num_nodes, groups));
  const BlockScatterMap map(pattern, groups);
  ASSERT_EQ(map.groupSize(), groups.rows());
  ASSERT_EQ(map.numGroups(), groups.cols());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::SparseMatrix<double> assembled = pattern;
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * num_nodes, 3 * num_nodes);
  for (int g = 0; g < groups.cols(); ++g) {
    Eigen::Matrix<double, Size, Size> Ke;
    for (Eigen::Index i = 0; i < Ke.size(); ++i) Ke.data()[i] = u(rng);
    map.add(g, Ke, assembled.valuePtr());
    for (int c = 0; c < Size; ++c)
      for (int r = 0; r < Size; ++r)
        dense(3 * groups(r / 3, g) + r % 3, 3 * groups(c / 3, g) + c % 3) += Ke(r, c);
  }
  const Eigen::MatrixXd assembled_dense(assembled);
  for (Eigen::Index c = 0; c < dense.cols(); ++c)
    for (Eigen::Index r = 0; r < dense.rows(); ++r)
      ASSERT_EQ(assembled_dense(r, c), dense(r, c)) << "entry (" << r << ", " << c << ")";
}

TEST(BlockSparsity, TetMeshPatternHasTheBlocksOfEveryElement) {
  std::mt19937 rng(11);
  const TetMesh mesh = test::jitteredLattice(3, 1.0, 0.1, rng);
  expectScatterAssemblesGroupMatrices<12>(mesh.numNodes(), mesh.elements);
  // Node 13 in no element.
  expectScatterAssemblesGroupMatrices<12>(mesh.numNodes() + 1, withIsolatedNode(mesh.elements, 13));
}

TEST(BlockSparsity, Tet10MeshScatter) {
  std::mt19937 rng(5);
  const TetMesh mesh = test::toTet10(test::jitteredLattice(2, 1.0, 0.1, rng));
  expectScatterAssemblesGroupMatrices<30>(mesh.numNodes(), mesh.elements);
  // Node 0 in no element.
  expectScatterAssemblesGroupMatrices<30>(mesh.numNodes() + 1, withIsolatedNode(mesh.elements, 0));
}

TEST(BlockSparsity, SpringsAndIsolatedNodes) {
  // Two-node groups (springs), a spring listed twice, and nodes 5, 6 in no group.
  Eigen::MatrixXi springs(2, 5);
  springs << 0, 1, 2, 4, 1, 1, 2, 3, 0, 2;
  expectScatterAssemblesGroupMatrices<6>(7, springs);
}

TEST(BlockSparsity, GroupWithARepeatedNode) {
  // Group (3, 3) sums its four blocks into node 3's diagonal block, in local column-major order.
  Eigen::MatrixXi groups(2, 3);
  groups << 3, 0, 3, 3, 3, 2;
  expectScatterAssemblesGroupMatrices<6>(5, groups);
}

}  // namespace
}  // namespace surgical_sim::core
