#pragma once

#include <Eigen/Core>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Procedural tetrahedral meshes, in metres. Every generated element is positively oriented and
/// the meshes are conforming. Hexahedral cells are split into 6 tetrahedra around their main
/// diagonal (from the cell's min corner to its max corner), which makes the split of every cell
/// face identical seen from both cells.

/// Axis-aligned box [min_corner, min_corner + size] split into cells.x * cells.y * cells.z cells.
/// @param min_corner lowest corner [m], finite.
/// @param size edge lengths along x, y, z [m], each finite and > 0.
/// @param cells number of cells along x, y, z, each >= 1.
/// @param type Tet4, or Tet10 (mid-edge nodes at the straight edge midpoints).
/// @return mesh with (cells.x+1)(cells.y+1)(cells.z+1) corner nodes (node i + (cells.x+1)(j +
///         (cells.y+1) k) at grid point (i, j, k)) and 6 cells.x cells.y cells.z elements.
/// @throws std::invalid_argument naming the offending parameter.
TetMesh makeBox(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& size,
                const Eigen::Vector3i& cells, ElementType type);

/// Rectangular beam along x: x in [0, length], y in [-width/2, width/2], z in [-height/2,
/// height/2] (a makeBox()).
/// @param length beam length along x [m], finite and > 0.
/// @param width extent along y [m], finite and > 0.
/// @param height extent along z [m], finite and > 0.
/// @param cells number of cells along x, y, z, each >= 1.
/// @param type Tet4 or Tet10.
/// @throws std::invalid_argument naming the offending parameter, e.g.
///         "makeBeam: cells.x = 0 must be >= 1".
TetMesh makeBeam(double length, double width, double height, const Eigen::Vector3i& cells,
                 ElementType type);

/// Prism along x (x in [0, length]) with a regular hexagonal cross-section in the y-z plane,
/// centred on the x axis, with corners at (y, z) = side (cos(60° s), sin(60° s)), s = 0..5.
/// The hexagon is split into 6 triangular sectors, each subdivided into rings^2 triangles
/// (rings layers from the axis outwards); each triangle is extruded into cells_along prisms,
/// each split into 3 tetrahedra with diagonals chosen from the global node order so neighbouring
/// prisms conform. The cross-section area is exactly (3 sqrt(3) / 2) side^2.
/// @param side hexagon side length = circumradius [m], finite and > 0.
/// @param length prism length along x [m], finite and > 0.
/// @param cells_along number of layers along x, >= 1.
/// @param rings number of triangle layers from the axis to the hexagon boundary, >= 1.
/// @param type Tet4 or Tet10.
/// @return mesh with (1 + 3 rings (rings + 1)) (cells_along + 1) corner nodes and
///         18 rings^2 cells_along elements.
/// @throws std::invalid_argument naming the offending parameter.
TetMesh makeHexagonalBeam(double side, double length, int cells_along, int rings, ElementType type);

/// Smooth organ-like blob centred on the origin (a liver-lobe-like stand-in for a scanned organ).
///
/// A box mesh of [-1, 1]^3 with cells_per_axis cells per axis is mapped onto the unit ball by
/// u = r S(p / r), where r = max(|p_x|, |p_y|, |p_z|) and S is the smooth cube-to-sphere map
/// S_x(q) = q_x sqrt(1 - q_y^2/2 - q_z^2/2 + q_y^2 q_z^2/3) (and cyclic): the boundary nodes lie
/// on the sphere with the smooth, nearly uniform spacing of S, and the interior map (smooth in
/// each of the 6 pyramids from the centre to a cube face) keeps a Jacobian determinant bounded
/// away from 0 at every resolution. (S applied to the whole cube is singular at the cube corners
/// and inverts corner elements on fine grids.) The ball is then given a deterministic asymmetric
/// shape v = (u_x, u_y + 0.1 u_x^2, (0.8 - 0.2 u_x) u_z), with Jacobian determinant
/// 0.8 - 0.2 u_x > 0: thick at -x, tapering like a liver lobe towards +x, slightly curved in y.
/// The result is scaled by semi_axes (a, b, c): it fits in [-a, a] x [-b, b] x [-0.83 c, 0.83 c]
/// and its volume tends to 0.8 (4/3) pi a b c under refinement. Tet10 mid-edge nodes are mapped too
/// (curved boundary).
/// @param semi_axes extents (a, b, c) along x, y, z [m], each finite and > 0.
/// @param cells_per_axis cells per axis of the underlying cube, >= 1; the mesh has
///        (cells_per_axis + 1)^3 corner nodes and 6 cells_per_axis^3 elements.
/// @param type Tet4 or Tet10.
/// @throws std::invalid_argument naming the offending parameter.
TetMesh makeOrganBlob(const Eigen::Vector3d& semi_axes, int cells_per_axis, ElementType type);

/// Converts a Tet4 mesh into a Tet10 mesh by adding one node at the midpoint of every unique
/// edge, shared by all elements around the edge. Corner nodes keep their indices; new nodes are
/// numbered after them in order of first appearance (element by element, edges in Gmsh order
/// 4:(0,1) 5:(1,2) 6:(0,2) 7:(0,3) 8:(2,3) 9:(1,3)).
/// @param tet4 mesh of type Tet4 with node indices in range.
/// @throws std::invalid_argument if tet4 is not Tet4 or references a missing node.
TetMesh promoteToTet10(const TetMesh& tet4);

}  // namespace surgical_sim::core
