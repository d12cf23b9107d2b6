#pragma once

#include <string>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Reads the tetrahedra of an ASCII Gmsh mesh file, format 2.2 or 4.1 (detected from
/// $MeshFormat).
///
/// Only tetrahedra are kept: element type 4 gives a Tet4 mesh, type 11 a Tet10 mesh (same node
/// order as Gmsh); points, lines, triangles and other element types are ignored, as are sections
/// other than $MeshFormat, $Nodes and $Elements. Nodes are renumbered compactly in file order
/// (Gmsh tags may be sparse) and nodes not used by any tetrahedron are dropped. Element
/// orientation is kept as in the file (check it with checkMesh()).
///
/// @param path file to read.
/// @param metres_per_unit size of the file's length unit [m/unit], e.g. 0.001 for a file in
///        millimetres (see lengthUnitToMetres()); finite and > 0.
/// @return mesh with nodes in metres.
/// @throws std::invalid_argument if metres_per_unit is not finite and > 0.
/// @throws std::runtime_error "path:line: what" for an unreadable file, a binary file, an
///         unsupported version, a truncated section, an unknown section without its $End line,
///         a bad or non-finite number, a negative count or one above 10^8 or above what the rest
///         of the file can hold (checked before reading the entries), a node or element tag
///         defined twice, an element referencing an unknown node tag, a file mixing Tet4 and
///         Tet10 elements, or a file without tetrahedra; "path: what" if a coordinate overflows
///         when scaled to metres.
TetMesh readGmsh(const std::string& path, double metres_per_unit);

}  // namespace surgical_sim::core
