#include "surgical_sim/core/mesh/surface_closure.h"

#include <algorithm>
#include <array>
#include <vector>

namespace surgical_sim::core {

SurfaceClosure checkSurfaceClosure(const Eigen::Matrix3Xi& triangles) {
  // (lower vertex, higher vertex, +1 if used from lower to higher else -1)
  std::vector<std::array<int, 3>> uses;
  uses.reserve(static_cast<std::size_t>(3 * triangles.cols()));
  for (Eigen::Index t = 0; t < triangles.cols(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles(k, t), b = triangles((k + 1) % 3, t);
      uses.push_back({std::min(a, b), std::max(a, b), a < b ? 1 : -1});
    }
  std::sort(uses.begin(), uses.end());
  SurfaceClosure out;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    int balance = 0;
    for (; j < uses.size() && uses[j][0] == uses[i][0] && uses[j][1] == uses[i][1]; ++j)
      balance += uses[j][2];
    if (balance != 0) ++out.open_edges;
    if (j - i > 2) ++out.pinched_edges;
    i = j;
  }
  return out;
}

}  // namespace surgical_sim::core
