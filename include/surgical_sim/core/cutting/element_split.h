#pragma once

#include <Eigen/Core>
#include <array>

namespace surgical_sim::core {

/// Fragments of one tetrahedron under the cut edges of the virtual node algorithm.
struct ElementSplit {
  /// Number of fragments, 1..4 (1: the element is not split).
  int count = 1;
  /// masks[f], f < count: bit i set iff local corner i belongs to fragment f. The masks partition
  /// {0, 1, 2, 3}; fragments are ordered by their lowest corner.
  std::array<int, 4> masks{0xF, 0, 0, 0};
  /// Material volume fraction of fragment f [-], f < count (fragmentVolumeFractions()); they sum
  /// to 1, so copies weighing rho V_e times their fraction conserve the element's mass.
  std::array<double, 4> fractions{1.0, 0.0, 0.0, 0.0};
};

/// Splits one tetrahedron into fragments: the connected components of its 4 corners over its
/// uncut edges. An element whose cut edges do not separate its corners (a cut front inside it)
/// stays one fragment.
/// @param X rest corner positions [m], shape 3 x 4, positively oriented.
/// @param edge_cut whether local edge k (kTetLocalEdges order) is cut.
/// @param edge_s cut point of local edge k = (i, j), i < j, as the parameter from corner i towards
///        corner j, in [0, 1] (read only on edges between different fragments).
/// Stateless, allocation-free.
ElementSplit splitElement(const Eigen::Matrix<double, 3, 4>& X, const std::array<bool, 6>& edge_cut,
                          const std::array<double, 6>& edge_s);

}  // namespace surgical_sim::core
