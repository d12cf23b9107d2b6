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

/// Element-to-nonzero map for scatter-adding dense group matrices into `pattern.valuePtr()`
/// (`pattern` from makeBlockPattern() over the same groups: full 3 x 3 node blocks):
/// entry [g (3k)^2 + c 3k + r] is the value index of global entry (dof(r), dof(c)), where local
/// dof r = 3 a + i is component i of node groups(a, g). Size g (3k)^2. Column-major local order,
/// so a column-major (3k x 3k) element matrix scatters with one linear loop.
std::vector<int> makeScatterMap(const Eigen::SparseMatrix<double>& pattern,
                                const Eigen::MatrixXi& groups);

}  // namespace surgical_sim::core
