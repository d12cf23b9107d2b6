#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace surgical_sim::core {

/// Skinning weights of one point (an integration sample or a mapped point) on its neighbouring
/// rigid nodes, evaluated once at rest positions (total Lagrangian): w_i [-] and their gradients
/// grad w_i with respect to the rest position [1/m]. The three shape functions below form a
/// partition of unity (sum w_i = 1, sum grad w_i = 0), which makes the rest deformation gradient
/// the identity and reproduces rigid motions exactly.
struct SampleWeights {
  std::vector<int> nodes;                  ///< rigid node indices, distinct
  std::vector<double> weights;             ///< w_i, same length as nodes
  std::vector<Eigen::Vector3d> gradients;  ///< grad w_i [1/m], same length as nodes
};

/// Linear tetrahedral (barycentric) weights of point p in the tet whose corners are rigid nodes
/// `nodes` at rest positions `corners` [m]: w = P^-1 (p, 1), gradients constant per tet.
/// p may lie outside the tet (linear extrapolation).
/// @throws std::invalid_argument if the tet is degenerate (|det| <= 1e-12 longest edge^3) or an
///         input is not finite
SampleWeights tetBarycentricWeights(const std::array<int, 4>& nodes,
                                    const std::array<Eigen::Vector3d, 4>& corners,
                                    const Eigen::Vector3d& p);

/// Trilinear weights of point p in the axis-aligned cell [cell_min, cell_min + cell_size] whose
/// corner c = cx + 2 cy + 4 cz (cx, cy, cz in {0, 1}) is rigid node nodes[c]. p may lie outside
/// the cell (multilinear extrapolation).
/// @throws std::invalid_argument if a cell size is not finite and > 0 or p is not finite
SampleWeights trilinearWeights(const std::array<int, 8>& nodes, const Eigen::Vector3d& cell_min,
                               const Eigen::Vector3d& cell_size, const Eigen::Vector3d& p);

/// Shepard (inverse distance) weights of point p on its `neighbours` nearest rigid nodes:
/// phi_i = d_i^-exponent, w_i = phi_i / sum phi, grad w_i = (grad phi_i - w_i sum grad phi) /
/// sum phi. Needs no moment matrix, so collinear and coplanar node layouts work.
/// @param node_positions rest positions of all rigid nodes [m], finite
/// @param neighbours number of nearest nodes used, in [1, node_positions.size()]
/// @param exponent Shepard exponent [-], finite and > 0
/// @throws std::invalid_argument for an out-of-range parameter, or if p coincides with a node
///         (distance <= 1e-9 times the largest neighbour distance: the weights are singular there)
SampleWeights shepardWeights(const std::vector<Eigen::Vector3d>& node_positions,
                             const Eigen::Vector3d& p, int neighbours, double exponent);

/// Checks that w is usable by a model of num_nodes rigid nodes: equal lengths, at least one
/// node, distinct node indices in [0, num_nodes), finite values, sum w_i = 1 within 1e-9 and
/// |sum grad w_i| <= 1e-9 sum |grad w_i| (partition of unity).
/// @throws std::invalid_argument naming `what` and the failed condition with its value
void checkSampleWeights(const SampleWeights& w, int num_nodes, const std::string& what);

}  // namespace surgical_sim::core
