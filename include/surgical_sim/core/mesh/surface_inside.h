#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Volume enclosed by a closed, outward-oriented triangle surface, by the divergence theorem
/// [m^3] (sum over triangles of a . (b x c) / 6; negative for an inward-oriented one).
double enclosedVolume(const TriMesh& surface);

/// Which points of a regular lattice lie inside a closed triangle surface.
///
/// Lattice point (i, j, k), 0 <= i < count.x (likewise j, k), sits at
/// origin + pitch (i + 1/2, j + 1/2, k + 1/2); the result holds 1 (inside) or 0 at
/// i + count.x (j + count.y k). A point is inside when the ray from it along -z crosses the
/// surface an odd number of times (ray parity: the surface's orientation does not matter).
/// Crossings are found column by column: each triangle is intersected with the vertical lines
/// through the lattice columns its xy-projection covers. A line through an edge or a vertex is
/// decided by symbolic perturbation (the line moved by (e, e^2), e -> 0+, with every edge's
/// orientation evaluated with its endpoints in one fixed order), so on a closed surface every
/// line crosses an even number of times and no crossing is counted twice or missed. A point on
/// a face crossed by its column (e.g. a horizontal face) counts as inside; a column on a
/// vertical face goes with the perturbation. Allocates; time O(lattice points + covered columns).
/// @param surface closed triangle surface [m] (e.g. checkSurfaceClosure() without open edges);
///        on an open one, a column with an odd crossing count ignores its last crossing.
/// @param origin lattice corner [m]; @param pitch lattice spacing [m], finite and > 0;
/// @param count points per axis, each >= 1.
/// @throws std::invalid_argument for a vertex index out of range, a non-finite vertex, pitch or
///         origin, or a count < 1.
std::vector<std::uint8_t> markInsideLattice(const TriMesh& surface, const Eigen::Vector3d& origin,
                                            double pitch, const Eigen::Vector3i& count);

}  // namespace surgical_sim::core
