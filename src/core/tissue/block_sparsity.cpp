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
  std::vector<Eigen::Triplet<double>> triplets;
  for (int i = 0; i < num_nodes; ++i) {
    auto& adj = adjacency[static_cast<size_t>(i)];
    std::sort(adj.begin(), adj.end());
    adj.erase(std::unique(adj.begin(), adj.end()), adj.end());
    for (int j : adj) {
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) triplets.emplace_back(3 * j + r, 3 * i + c, 0.0);
      }
    }
  }
  Eigen::SparseMatrix<double> pattern(3 * num_nodes, 3 * num_nodes);
  pattern.setFromTriplets(triplets.begin(), triplets.end());
  pattern.makeCompressed();
  return pattern;
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
      for (int r = 0; r < dofs; ++r) {
        const int row = 3 * groups(r / 3, g) + r % 3;
        const int* it = std::lower_bound(inner + outer[col], inner + outer[col + 1], row);
        map.push_back(static_cast<int>(it - inner));
      }
    }
  }
  return map;
}

}  // namespace surgical_sim::core
