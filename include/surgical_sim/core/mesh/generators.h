#pragma once

#include <array>

#include <Eigen/Core>

#include "surgical_sim/core/common/named_enum.h"
#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Procedural tetrahedral meshes, in metres. Every generated element is positively oriented and
/// the meshes are conforming (every interior face is shared by exactly two elements).

/// How makeBox() and makeBeam() split each hexahedral grid cell into tetrahedra. Both splits cut
/// every cell face along the same diagonal seen from both cells sharing it.
enum class CellSplit {
  /// 5 tetrahedra: a central one on the 4 cell corners whose grid indices (i, j, k) have an even
  /// sum, and one at each of the other 4 corners (that corner and its 3 edge neighbours); every
  /// cell face is cut along its diagonal between even corners, so the orientation alternates
  /// from cell to cell. The mesh is invariant under the mirror x -> 2 m_x - x about the box's
  /// mid-plane along each axis whose cell count is even (likewise y, z): a load and supports
  /// symmetric about such a plane give a symmetric response. (No split of an odd number of
  /// cells into tetrahedra on the grid nodes can be: the middle cell's faces crossing the plane
  /// would need both diagonals.) 5 elements per cell, the central one with 1/3 of its volume.
  Symmetric,
  /// 6 tetrahedra around every cell's main diagonal from its min corner to its max corner (Kuhn
  /// split), the same in every cell, each with 1/6 of the cell volume. Not mirror-symmetric: a
  /// cantilever loaded in one symmetry plane also bends out of it.
  Diagonal,
};

/// Scene names (mesh.split): symmetric, diagonal.
inline constexpr std::array<EnumName<CellSplit>, 2> kCellSplitNames{{
    {CellSplit::Symmetric, "symmetric"},
    {CellSplit::Diagonal, "diagonal"},
}};

/// Axis-aligned box [min_corner, min_corner + size] split into cells.x * cells.y * cells.z cells.
/// @param min_corner lowest corner [m], finite.
/// @param size edge lengths along x, y, z [m], each finite and > 0.
/// @param cells number of cells along x, y, z, each >= 1.
/// @param type Tet4, or Tet10 (mid-edge nodes at the straight edge midpoints).
/// @param split cell split (CellSplit).
/// @return mesh with (cells.x+1)(cells.y+1)(cells.z+1) corner nodes (node i + (cells.x+1)(j +
///         (cells.y+1) k) at grid point (i, j, k)) and 5 (Symmetric) or 6 (Diagonal)
///         cells.x cells.y cells.z elements.
/// @throws std::invalid_argument naming the offending parameter.
TetMesh makeBox(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& size,
                const Eigen::Vector3i& cells, ElementType type,
                CellSplit split = CellSplit::Symmetric);

/// Rectangular beam along x: x in [0, length], y in [-width/2, width/2], z in [-height/2,
/// height/2] (a makeBox()). With the Symmetric split and even cells.y (cells.z) the mesh is
/// mirror-symmetric about the plane y = 0 (z = 0).
/// @param length beam length along x [m], finite and > 0.
/// @param width extent along y [m], finite and > 0.
/// @param height extent along z [m], finite and > 0.
/// @param cells number of cells along x, y, z, each >= 1.
/// @param type Tet4 or Tet10.
/// @param split cell split (CellSplit).
/// @throws std::invalid_argument naming the offending parameter, e.g.
///         "makeBeam: cells.x = 0 must be >= 1".
TetMesh makeBeam(double length, double width, double height, const Eigen::Vector3i& cells,
                 ElementType type, CellSplit split = CellSplit::Symmetric);

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

/// Smooth organ-like blob centred on the origin: a lobe mirror-symmetric about the planes x = 0,
/// y = 0 and z = 0, thickest at its centre and thinning towards its ends along x.
///
/// A box mesh of [-1, 1]^3 with cells_per_axis cells per axis is mapped onto the unit ball by
/// u = r S(p / r), where r = max(|p_x|, |p_y|, |p_z|) and S is the smooth cube-to-sphere map
/// S_x(q) = q_x sqrt(1 - q_y^2/2 - q_z^2/2 + q_y^2 q_z^2/3) (and cyclic): the boundary nodes lie
/// on the sphere with the smooth, nearly uniform spacing of S, and the interior map (smooth in
/// each of the 6 pyramids from the centre to a cube face) keeps a Jacobian determinant bounded
/// away from 0 at every resolution. (S applied to the whole cube is singular at the cube corners
/// and inverts corner elements on fine grids.) The ball is then tapered and scaled by
/// semi_axes (a, b, c): v = (a u_x, b u_y, c (1 - u_x^2 / 4) u_z), Jacobian determinant
/// a b c (1 - u_x^2 / 4) >= 3/4 a b c. The surface is therefore
///   (x/a)^2 + (y/b)^2 + (z / (c (1 - (x/a)^2 / 4)))^2 = 1:
/// its top is z = c (1 - (x/a)^2 / 4) sqrt(1 - (x/a)^2 - (y/b)^2) (highest point (0, 0, c),
/// bottom the mirror image, lowest point (0, 0, -c)), its outline in the plane z = 0 is the
/// ellipse (x/a)^2 + (y/b)^2 = 1 (ends at (+-a, 0, 0), sides at (0, +-b, 0)); it fits exactly in
/// [-a, a] x [-b, b] x [-c, c] and its volume tends to (19/20) (4/3) pi a b c under refinement
/// (boundary nodes lie on the surface; elements are straight-sided). The node set (and with even
/// cells_per_axis the connectivity) is invariant under each of x -> -x, y -> -y, z -> -z.
/// Tet10 mid-edge nodes are mapped too (curved boundary).
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
