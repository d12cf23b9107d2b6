#include "surgical_sim/core/tissue/block_sparsity.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace surgical_sim::core {
namespace {

/// The groups holding each node (compressed rows): occurrences of node i are
/// entries[offsets[i], offsets[i + 1]), each the position g k + a of groups(a, g).
struct NodeGroups {
  NodeGroups(int num_nodes, const Eigen::MatrixXi& groups)
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
  // Compressed columns directly: column 3 i + c holds rows 3 j + r of i's neighbours j.
  Eigen::SparseMatrix<double> pattern(3 * num_nodes, 3 * num_nodes);
  pattern.resizeNonZeros(static_cast<Eigen::Index>(9 * neighbours.size()));
  int* outer = pattern.outerIndexPtr();
  int* inner = pattern.innerIndexPtr();
  outer[0] = 0;
  int entry = 0;
  for (int i = 0; i < num_nodes; ++i) {
    for (int c = 0; c < 3; ++c) {
      for (int p = offsets[i]; p < offsets[i + 1]; ++p)
        for (int r = 0; r < 3; ++r) inner[entry++] = 3 * neighbours[static_cast<size_t>(p)] + r;
      outer[3 * i + c + 1] = entry;
    }
  }
  std::fill(pattern.valuePtr(), pattern.valuePtr() + entry, 0.0);
  return pattern;
}

BlockScatterMap::BlockScatterMap(const Eigen::SparseMatrix<double>& pattern,
                                 const Eigen::MatrixXi& groups)
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

}  // namespace surgical_sim::core
