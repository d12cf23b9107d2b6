#include "surgical_sim/core/tissue/block_sparsity.h"

#include <algorithm>

namespace surgical_sim::core {

Eigen::SparseMatrix<double> makeBlockPattern(int num_nodes, const Eigen::MatrixXi& groups) {
  std::vector<std::vector<int>> adjacency(static_cast<size_t>(num_nodes));
  for (Eigen::Index g = 0; g < groups.cols(); ++g) {
    for (Eigen::Index a = 0; a < groups.rows(); ++a) {
      for (Eigen::Index b = 0; b < groups.rows(); ++b) {
        adjacency[static_cast<size_t>(groups(a, g))].push_back(groups(b, g));
      }
    }
  }
  // Compressed columns directly: column 3 i + c holds rows 3 j + r of i's sorted neighbours j.
  std::vector<int> outer(static_cast<size_t>(3 * num_nodes + 1), 0);
  std::vector<int> inner;
  for (int i = 0; i < num_nodes; ++i) {
    auto& adj = adjacency[static_cast<size_t>(i)];
    std::sort(adj.begin(), adj.end());
    adj.erase(std::unique(adj.begin(), adj.end()), adj.end());
    for (int c = 0; c < 3; ++c) {
      for (int j : adj)
        for (int r = 0; r < 3; ++r) inner.push_back(3 * j + r);
      outer[static_cast<size_t>(3 * i + c + 1)] = static_cast<int>(inner.size());
    }
  }
  const std::vector<double> zeros(inner.size(), 0.0);
  return Eigen::SparseMatrix<double>(Eigen::Map<const Eigen::SparseMatrix<double>>(
      3 * num_nodes, 3 * num_nodes, static_cast<Eigen::Index>(inner.size()), outer.data(),
      inner.data(), zeros.data()));
}

std::vector<int> makeScatterMap(const Eigen::SparseMatrix<double>& pattern,
                                const Eigen::MatrixXi& groups) {
  const int dofs = 3 * static_cast<int>(groups.rows());
  std::vector<int> map;
  map.reserve(static_cast<size_t>(groups.cols()) * static_cast<size_t>(dofs * dofs));
  const int* outer = pattern.outerIndexPtr();
  const int* inner = pattern.innerIndexPtr();
  for (Eigen::Index g = 0; g < groups.cols(); ++g) {
    for (int c = 0; c < dofs; ++c) {
      const int col = 3 * groups(c / 3, g) + c % 3;
      // The 3 rows of a node block are consecutive in a column: one search per block.
      for (Eigen::Index b = 0; b < groups.rows(); ++b) {
        const int* it =
            std::lower_bound(inner + outer[col], inner + outer[col + 1], 3 * groups(b, g));
        const int first = static_cast<int>(it - inner);
        for (int r = 0; r < 3; ++r) map.push_back(first + r);
      }
    }
  }
  return map;
}

}  // namespace surgical_sim::core
