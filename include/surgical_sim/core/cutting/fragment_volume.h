#pragma once

#include <Eigen/Core>
#include <array>

namespace surgical_sim::core {

/// Local corner pairs of the 6 edges of a tetrahedron, in this order: (0,1) (0,2) (0,3) (1,2)
/// (1,3) (2,3). Cut parameters of an element are indexed the same way.
constexpr std::array<std::array<int, 2>, 6> kTetLocalEdges = {
    {{{0, 1}}, {{0, 2}}, {{0, 3}}, {{1, 2}}, {{1, 3}}, {{2, 3}}}};

/// Index (0..5) of the local edge joining local corners i != j (any order) in kTetLocalEdges.
int tetLocalEdge(int i, int j);

/// Smallest material fraction given to a fragment [-] (cuts through or next to a node would
/// otherwise give a copy no mass); fractions are renormalized to sum to 1 after clamping.
constexpr double kMinFragmentFraction = 1e-3;

/// Material volume fractions of the fragments of one tetrahedron cut by a surface that crosses
/// its edges at known points.
///
/// @param X rest corner positions [m], shape 3 x 4, positively oriented.
/// @param edge_s cut point of local edge k = (i, j), i < j, as the parameter from corner i
///        towards corner j, in [0, 1] (only edges between different fragments are read).
/// @param masks the fragments: bit i of masks[f] set iff local corner i belongs to fragment f;
///        masks[0 .. count) partition {0, 1, 2, 3}, with every edge between two fragments cut.
/// @param count number of fragments, 1..4.
/// @return fraction of the element volume in fragment f, for f < count; they sum to 1.
///
/// Formulas (exact for a planar cut): a single corner a cut off by points at fractions
/// s_ab, s_ac, s_ad along its edges is the tet (a, p_ab, p_ac, p_ad) of volume fraction
/// s_ab s_ac s_ad; a pair {a, b} separated from {c, d} is the prism with triangles
/// (a, p_ac, p_ad) and (b, p_bc, p_bd), split into 3 tets. With two fragments the other one gets
/// 1 - that; with more, a pair gets 1 - the singletons and four singletons are normalized.
/// Each fraction is then clamped to >= kMinFragmentFraction and all are renormalized.
std::array<double, 4> fragmentVolumeFractions(const Eigen::Matrix<double, 3, 4>& X,
                                              const std::array<double, 6>& edge_s,
                                              const std::array<int, 4>& masks, int count);

}  // namespace surgical_sim::core
