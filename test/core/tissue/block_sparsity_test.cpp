#include "surgical_sim/core/tissue/block_sparsity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <random>
#include <stdexcept>
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

/// The nodes each node couples with in a makeBlockPattern() pattern, ascending.
std::vector<std::vector<int>> coupledNodes(const Eigen::SparseMatrix<double>& pattern) {
  std::vector<std::vector<int>> rows(static_cast<size_t>(pattern.cols() / 3));
  for (Eigen::Index i = 0; i < pattern.cols() / 3; ++i)
    for (int p = pattern.outerIndexPtr()[3 * i]; p < pattern.outerIndexPtr()[3 * i + 1]; p += 3)
      rows[static_cast<size_t>(i)].push_back(pattern.innerIndexPtr()[p] / 3);
  return rows;
}

/// added[i]: the nodes node i couples with in `after` and not in `before`, ascending.
std::vector<std::vector<int>> addedCouplings(const Eigen::SparseMatrix<double>& before,
                                             const Eigen::SparseMatrix<double>& after) {
  const std::vector<std::vector<int>> was = coupledNodes(before), is = coupledNodes(after);
  std::vector<std::vector<int>> added(is.size());
  for (size_t i = 0; i < is.size(); ++i)
    std::set_difference(is[i].begin(), is[i].end(), was[i].begin(), was[i].end(),
                        std::back_inserter(added[i]));
  return added;
}

// Growing a pattern in place, step by step from empty and by random new groups (some nodes gaining
// nothing, some first coupled late), gives exactly the pattern built on all the groups at once.
TEST(BlockSparsity, PatternGrownInPlaceMatchesThePatternBuiltOnAllGroups) {
  std::mt19937 rng(11);
  const int n = 40;
  std::uniform_int_distribution<int> node(0, n - 1);
  Eigen::SparseMatrix<double> grown(3 * n, 3 * n);
  Eigen::SparseMatrix<double> before(3 * n, 3 * n);
  Eigen::MatrixXi groups(4, 0);
  for (int round = 0; round < 30; ++round) {
    const int count = round == 0 ? 12 : 1 + round % 3;
    Eigen::MatrixXi all(4, groups.cols() + count);
    all.leftCols(groups.cols()) = groups;
    for (int g = 0; g < count; ++g) {
      // Nodes near one another (a local neighbourhood), distinct within the group.
      const int base = node(rng) % (n - 6);
      std::vector<int> pick{base, base + 1, base + 3, base + 6};
      std::shuffle(pick.begin(), pick.end(), rng);
      all.col(groups.cols() + g) = Eigen::Map<const Eigen::Vector4i>(pick.data());
    }
    groups = all;
    const Eigen::SparseMatrix<double> after = makeBlockPattern(n, groups);
    growBlockPattern(addedCouplings(before, after), grown);
    expectSameStructure(grown, after);
    before = after;
  }
  growBlockPattern(std::vector<std::vector<int>>(n), grown);  // nothing added: unchanged
  expectSameStructure(grown, before);
  Eigen::SparseMatrix<double> wrong(3 * n - 3, 3 * n - 3);
  EXPECT_THROW(growBlockPattern(std::vector<std::vector<int>>(n), wrong), std::invalid_argument);
}

/// Values of `pattern` after scatter-adding the same random matrix per group through `map`.
Eigen::VectorXd scattered(const BlockScatterMap& map, const Eigen::SparseMatrix<double>& pattern) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::SparseMatrix<double> assembled = pattern;
  for (int g = 0; g < map.numGroups(); ++g) {
    Eigen::Matrix<double, 12, 12> Ke;
    for (Eigen::Index i = 0; i < Ke.size(); ++i) Ke.data()[i] = u(rng);
    map.add(g, Ke, assembled.valuePtr());
  }
  return Eigen::Map<const Eigen::VectorXd>(assembled.valuePtr(), assembled.nonZeros());
}

// A map edited in place (its pattern grown by a new group's couplings, the group appended, the
// first group removed) scatters exactly as a map built on the final groups and pattern.
TEST(BlockSparsity, EditedMapMatchesAMapBuiltOnTheFinalGroups) {
  Eigen::MatrixXi groups(4, 3);
  groups << 0, 1, 2, 1, 2, 3, 2, 3, 4, 3, 4, 5;
  Eigen::MatrixXi all(4, 4);
  all << groups, Eigen::Vector4i(4, 5, 6, 7);
  const Eigen::SparseMatrix<double> before = makeBlockPattern(8, groups);
  const Eigen::SparseMatrix<double> after = makeBlockPattern(8, all);
  const std::vector<std::vector<int>> added = addedCouplings(before, after);
  ASSERT_EQ(added[7].size(), 4u);  // 4, 5, 6, 7: node 7 was in no group
  Eigen::SparseMatrix<double> grown = before;
  growBlockPattern(added, grown);
  expectSameStructure(grown, after);

  BlockScatterMap map(before, groups);
  EXPECT_THROW(map.setGroup(before, 3, all.col(3).data()), std::invalid_argument);
  map.followGrownPattern(groups, added);
  map.setGroup(after, 3, all.col(3).data());
  map.removeGroup(0);
  Eigen::MatrixXi final_groups(4, 3);
  final_groups << all.col(3), all.col(1), all.col(2);
  const BlockScatterMap fresh(after, final_groups);
  ASSERT_EQ(map.numGroups(), 3);
  EXPECT_EQ(scattered(map, after), scattered(fresh, after));
}

}  // namespace
}  // namespace surgical_sim::core
