#include "surgical_sim/core/cutting/element_split.h"

#include "surgical_sim/core/cutting/fragment_volume.h"

namespace surgical_sim::core {

ElementSplit splitElement(const Eigen::Matrix<double, 3, 4>& X, const std::array<bool, 6>& edge_cut,
                          const std::array<double, 6>& edge_s) {
  // Component of each corner: merged along every uncut edge (label of the lower corner wins).
  std::array<int, 4> component{0, 1, 2, 3};
  for (int k = 0; k < 6; ++k) {
    if (edge_cut[k]) continue;
    const int from = component[kTetLocalEdges[k][1]], to = component[kTetLocalEdges[k][0]];
    for (int& c : component)
      if (c == from) c = to;
  }
  ElementSplit split;
  split.count = 0;
  split.masks = {0, 0, 0, 0};
  std::array<int, 4> fragment_of{-1, -1, -1, -1};  // per component label
  for (int i = 0; i < 4; ++i) {
    int& f = fragment_of[component[i]];
    if (f < 0) f = split.count++;
    split.masks[f] |= 1 << i;
  }
  split.fractions = fragmentVolumeFractions(X, edge_s, split.masks, split.count);
  return split;
}

}  // namespace surgical_sim::core
