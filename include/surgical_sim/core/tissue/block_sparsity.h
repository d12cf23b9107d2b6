#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

namespace surgical_sim::core {

/// Stiffness sparsity pattern of 3 dofs per node: every pair of nodes that share a column of
/// `groups` (an element's nodes, or a spring's two end nodes) couples with a full 3 x 3 block.
/// @param num_nodes number of nodes n; the pattern is 3n x 3n, compressed column, values zero.
/// @param groups node indices, shape k x g (one group per column), indices in [0, n).
Eigen::SparseMatrix<double> makeBlockPattern(int num_nodes, const Eigen::MatrixXi& groups);
/// Grows `pattern` in place so that node i also couples with the nodes added[i] (ascending,
/// distinct, none coupled with i before; symmetric; n = added.size()). Only the columns from the
/// first node with additions on move, so the cost is the pattern's tail, not a rebuild; storage
/// that must grow takes a quarter of slack. Values stay zero.
/// @param pattern a 3n x 3n compressed pattern of 3 x 3 blocks with zero values (as built by
///        makeBlockPattern, or resized to 3n x 3n and empty).
/// @throws std::invalid_argument if the pattern is not 3n x 3n and compressed.
void growBlockPattern(const std::vector<std::vector<int>>& added,
                      Eigen::SparseMatrix<double>& pattern);

/// Group-to-nonzero map for scatter-adding dense group matrices into the values of a pattern from
/// makeBlockPattern() over the same groups.
///
/// The pattern stores node i's 3 columns with the same rows, 3 per neighbour node, so with
/// node_a = groups(a, g), the entry of local row 3 b + r and column 3 a + c (r, c in 0..2) is at
/// value index first(a, b) + c len(a) + r, where first(a, b) is the index of row 3 node_b in
/// column 3 node_a and len(a) the length of that column. Per group the map stores the k^2 values
/// first(a, b) (at a k + b) followed by the k values len(a): k (k + 1) ints (20 per Tet4 element,
/// 110 per Tet10, 6 per spring) instead of (3k)^2 for one index per entry.
class BlockScatterMap {
 public:
  BlockScatterMap() = default;
  /// Linear time in the pattern size plus the number of group entries; allocates.
  /// @param pattern makeBlockPattern(n, groups) or a pattern that couples at least the same nodes,
  ///        compressed (its values are not used).
  /// @param groups node indices, shape k x g, indices in [0, n).
  BlockScatterMap(const Eigen::SparseMatrix<double>& pattern,
                  const Eigen::Ref<const Eigen::MatrixXi>& groups);

  /// Sets group `group` (in [0, numGroups()], numGroups() appends one) to the k nodes `nodes`,
  /// each pair of which must be coupled in `pattern` (k^2 binary searches in its columns).
  /// @throws std::invalid_argument naming two nodes that the pattern does not couple.
  void setGroup(const Eigen::SparseMatrix<double>& pattern, int group, const int* nodes);
  /// Follows the growth of the map's pattern by the couplings `added` (added[i]: the nodes newly
  /// coupled with node i, ascending, none coupled before; symmetric; size n): each group then
  /// scatters into the grown pattern. Linear in the map's size plus n.
  /// @param groups the map's groups, k x numGroups().
  void followGrownPattern(const Eigen::Ref<const Eigen::MatrixXi>& groups,
                          const std::vector<std::vector<int>>& added);
  /// Removes group `group` in [0, numGroups()): the last group takes its index.
  void removeGroup(int group);

  /// Nodes per group k.
  int groupSize() const { return k_; }
  /// Number of groups g.
  int numGroups() const { return k_ == 0 ? 0 : static_cast<int>(map_.size()) / (k_ * (k_ + 1)); }

  /// values[entry of (dof(r), dof(c))] += Ke(r, c) for every local row and column of `group`,
  /// where local dof 3 a + i is component i of node groups(a, group). Entries in local
  /// column-major order, so a node repeated in a group sums in the same order as a dense loop.
  /// @param Ke the group matrix, 3 groupSize() x 3 groupSize() (fixed or dynamic size).
  /// @param values the pattern's valuePtr() (or that of a matrix with the same pattern).
  template <int Size, int Options, int MaxSize>
  void add(int group, const Eigen::Matrix<double, Size, Size, Options, MaxSize, MaxSize>& Ke,
           double* values) const {
    static_assert(Size == Eigen::Dynamic || Size % 3 == 0,
                  "BlockScatterMap::add: Size must be 3 k");
    const int kNodes = Size == Eigen::Dynamic ? k_ : Size / 3;
    const int* first = map_.data() + static_cast<size_t>(group) * (kNodes * (kNodes + 1));
    const int* len = first + kNodes * kNodes;
    const double* ke = Ke.data();
    for (int a = 0; a < kNodes; ++a) {
      for (int c = 0; c < 3; ++c) {
        const int offset = c * len[a];
        for (int b = 0; b < kNodes; ++b) {
          double* block = values + first[a * kNodes + b] + offset;
          for (int r = 0; r < 3; ++r) block[r] += *ke++;
        }
      }
    }
  }

 private:
  int k_ = 0;
  std::vector<int> map_;  ///< per group: first(a, b) at a k + b, then len(a) at k^2 + a
};

}  // namespace surgical_sim::core
