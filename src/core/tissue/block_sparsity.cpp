#include "surgical_sim/core/tissue/block_sparsity.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace surgical_sim::core {
namespace {

/// The groups holding each node (compressed rows): occurrences of node i are
/// entries[offsets[i], offsets[i + 1]), each the position g k + a of groups(a, g).
struct NodeGroups {
  NodeGroups(int num_nodes, const Eigen::Ref<const Eigen::MatrixXi>& groups)
      : offsets(static_cast<size_t>(num_nodes + 1), 0),
        entries(static_cast<size_t>(groups.size())) {
    const int* node = groups.data();
    for (Eigen::Index p = 0; p < groups.size(); ++p) ++offsets[static_cast<size_t>(node[p] + 1)];
    for (int i = 0; i < num_nodes; ++i) offsets[i + 1] += offsets[i];
    std::vector<int> next(offsets.begin(), offsets.end() - 1);
    for (Eigen::Index p = 0; p < groups.size(); ++p) {
      entries[static_cast<size_t>(next[static_cast<size_t>(node[p])]++)] = static_cast<int>(p);
    }
  }

  std::vector<int> offsets;
  std::vector<int> entries;
};

}  // namespace

Eigen::SparseMatrix<double> makeBlockPattern(int num_nodes, const Eigen::MatrixXi& groups) {
  const NodeGroups node_groups(num_nodes, groups);
  const auto k = static_cast<int>(groups.rows());
  // Sorted distinct neighbours j of each node i (compressed rows), found with a marker per node.
  std::vector<int> offsets(static_cast<size_t>(num_nodes + 1), 0);
  std::vector<int> neighbours;
  neighbours.reserve(node_groups.entries.size() * static_cast<size_t>(k));
  std::vector<int> marker(static_cast<size_t>(num_nodes), -1);
  for (int i = 0; i < num_nodes; ++i) {
    for (int p = node_groups.offsets[i]; p < node_groups.offsets[i + 1]; ++p) {
      const int* group = groups.data() + node_groups.entries[static_cast<size_t>(p)] / k * k;
      for (int b = 0; b < k; ++b) {
        if (marker[static_cast<size_t>(group[b])] == i) continue;
        marker[static_cast<size_t>(group[b])] = i;
        neighbours.push_back(group[b]);
      }
    }
    std::sort(neighbours.begin() + offsets[i], neighbours.end());
    offsets[i + 1] = static_cast<int>(neighbours.size());
  }
  // Column 3 i + c holds rows 3 j + r of node i's neighbours j.
  Eigen::SparseMatrix<double> pattern(3 * num_nodes, 3 * num_nodes);
  pattern.resizeNonZeros(9 * static_cast<Eigen::Index>(neighbours.size()));
  int* outer = pattern.outerIndexPtr();
  int* inner = pattern.innerIndexPtr();
  outer[0] = 0;
  int entry = 0;
  for (int i = 0; i < num_nodes; ++i) {
    const int column = entry;
    for (int p = offsets[static_cast<size_t>(i)]; p < offsets[static_cast<size_t>(i) + 1]; ++p)
      for (int r = 0; r < 3; ++r) inner[entry++] = 3 * neighbours[static_cast<size_t>(p)] + r;
    const int length = entry - column;
    outer[3 * i + 1] = entry;
    for (int c = 1; c < 3; ++c) {  // the node's other columns have the same rows
      std::copy(inner + column, inner + column + length, inner + entry);
      entry += length;
      outer[3 * i + c + 1] = entry;
    }
  }
  std::fill(pattern.valuePtr(), pattern.valuePtr() + entry, 0.0);
  return pattern;
}

void growBlockPattern(const std::vector<std::vector<int>>& added,
                      Eigen::SparseMatrix<double>& pattern) {
  const auto n = static_cast<Eigen::Index>(added.size());
  if (pattern.rows() != 3 * n || pattern.cols() != 3 * n || !pattern.isCompressed()) {
    throw std::invalid_argument(
        "growBlockPattern: the pattern is " + std::to_string(pattern.rows()) + " x " +
        std::to_string(pattern.cols()) + (pattern.isCompressed() ? "" : ", not compressed") +
        ", expected a compressed " + std::to_string(3 * n) + " x " + std::to_string(3 * n));
  }
  Eigen::Index first = 0;
  while (first < n && added[static_cast<size_t>(first)].empty()) ++first;
  if (first == n) return;
  Eigen::Index shift = 0;  // entries added before the node at hand
  for (const std::vector<int>& extra : added) shift += 9 * static_cast<Eigen::Index>(extra.size());
  const Eigen::Index old_size = pattern.nonZeros(), new_size = old_size + shift;
  if (pattern.data().allocatedSize() < new_size)
    pattern.data().reserve(new_size - old_size + new_size / 4);
  pattern.resizeNonZeros(new_size);
  int* outer = pattern.outerIndexPtr();
  int* inner = pattern.innerIndexPtr();
  // From the last node back: every entry moves to an index at least its own, so moving (and
  // merging in the added rows) from the back never overwrites an entry still to be read.
  outer[3 * n] = static_cast<int>(new_size);
  for (Eigen::Index i = n - 1; i >= first; --i) {
    const std::vector<int>& extra = added[static_cast<size_t>(i)];
    shift -= 9 * static_cast<Eigen::Index>(extra.size());
    const int old_start = outer[3 * i];
    const int old_length = outer[3 * i + 1] - old_start;
    const int new_length = old_length + 3 * static_cast<int>(extra.size());
    const int new_start = old_start + static_cast<int>(shift);
    for (int c = 2; c >= 0; --c) {
      int* const begin = inner + old_start + c * old_length;
      int* source = begin + old_length;
      int* target = inner + new_start + (c + 1) * new_length;
      for (auto j = extra.rbegin(); j != extra.rend(); ++j) {
        while (source != begin && *(source - 1) > 3 * *j) *--target = *--source;
        for (int r = 2; r >= 0; --r) *--target = 3 * *j + r;
      }
      if (target != source) std::copy_backward(begin, source, target);
    }
    for (int c = 0; c < 3; ++c) outer[3 * i + c] = new_start + c * new_length;
  }
  std::fill(pattern.valuePtr() + old_size, pattern.valuePtr() + new_size, 0.0);
}

BlockScatterMap::BlockScatterMap(const Eigen::SparseMatrix<double>& pattern,
                                 const Eigen::Ref<const Eigen::MatrixXi>& groups)
    : k_(static_cast<int>(groups.rows())),
      map_(static_cast<size_t>(groups.cols()) * static_cast<size_t>(k_ * (k_ + 1))) {
  const auto num_nodes = static_cast<int>(pattern.cols() / 3);
  const NodeGroups node_groups(num_nodes, groups);
  const int* outer = pattern.outerIndexPtr();
  const int* inner = pattern.innerIndexPtr();
  // Per node i, position[j] is the index of row 3 j in column 3 i. Each group entry (a, g) at
  // node i then fills first(a, .) and len(a) of group g.
  std::vector<int> position(static_cast<size_t>(num_nodes), 0);
  for (int i = 0; i < num_nodes; ++i) {
    for (int p = outer[3 * i]; p < outer[3 * i + 1]; p += 3) {
      position[static_cast<size_t>(inner[p] / 3)] = p;
    }
    const int len = outer[3 * i + 1] - outer[3 * i];
    for (int p = node_groups.offsets[i]; p < node_groups.offsets[i + 1]; ++p) {
      const int entry = node_groups.entries[static_cast<size_t>(p)];
      const int g = entry / k_;
      const int a = entry % k_;
      const int* group = groups.data() + static_cast<Eigen::Index>(g) * k_;
      int* first = map_.data() + static_cast<size_t>(g) * static_cast<size_t>(k_ * (k_ + 1));
      for (int b = 0; b < k_; ++b) {
        first[a * k_ + b] = position[static_cast<size_t>(group[b])];
      }
      first[k_ * k_ + a] = len;
    }
  }
}

void BlockScatterMap::setGroup(const Eigen::SparseMatrix<double>& pattern, int group,
                               const int* nodes) {
  const size_t size = static_cast<size_t>(k_ * (k_ + 1));
  if (group == numGroups()) map_.resize(map_.size() + size);
  int* first = map_.data() + static_cast<size_t>(group) * size;
  const int* outer = pattern.outerIndexPtr();
  const int* inner = pattern.innerIndexPtr();
  for (int a = 0; a < k_; ++a) {
    const int* column = inner + outer[3 * nodes[a]];
    const int* column_end = inner + outer[3 * nodes[a] + 1];
    for (int b = 0; b < k_; ++b) {
      const int* row = std::lower_bound(column, column_end, 3 * nodes[b]);
      if (row == column_end || *row != 3 * nodes[b]) {
        throw std::invalid_argument("BlockScatterMap::setGroup: nodes " + std::to_string(nodes[a]) +
                                    " and " + std::to_string(nodes[b]) +
                                    " are not coupled in the pattern");
      }
      first[a * k_ + b] = static_cast<int>(row - inner);
    }
    first[k_ * k_ + a] = static_cast<int>(column_end - column);
  }
}

void BlockScatterMap::followGrownPattern(const Eigen::Ref<const Eigen::MatrixXi>& groups,
                                         const std::vector<std::vector<int>>& added) {
  // Column 3 i starts 9 entries later per block added to the nodes before i, and its rows after
  // row 3 j 3 entries later per block added to node i before j.
  std::vector<int> shift(added.size() + 1, 0);
  for (size_t i = 0; i < added.size(); ++i)
    shift[i + 1] = shift[i] + 9 * static_cast<int>(added[i].size());
  for (Eigen::Index g = 0; g < groups.cols(); ++g) {
    int* first = map_.data() + static_cast<size_t>(g) * static_cast<size_t>(k_ * (k_ + 1));
    for (int a = 0; a < k_; ++a) {
      const auto node = static_cast<size_t>(groups(a, g));
      const std::vector<int>& extra = added[node];
      if (extra.empty()) {  // the column only moves (most columns, and all before the first gain)
        if (shift[node] != 0)
          for (int b = 0; b < k_; ++b) first[a * k_ + b] += shift[node];
        continue;
      }
      for (int b = 0; b < k_; ++b) {
        const auto before = std::lower_bound(extra.begin(), extra.end(), groups(b, g));
        first[a * k_ + b] += shift[node] + 3 * static_cast<int>(before - extra.begin());
      }
      first[k_ * k_ + a] += 3 * static_cast<int>(extra.size());
    }
  }
}

void BlockScatterMap::removeGroup(int group) {
  const size_t size = static_cast<size_t>(k_ * (k_ + 1));
  std::copy(map_.end() - static_cast<std::ptrdiff_t>(size), map_.end(),
            map_.begin() + static_cast<std::ptrdiff_t>(group * size));
  map_.resize(map_.size() - size);
}

}  // namespace surgical_sim::core
