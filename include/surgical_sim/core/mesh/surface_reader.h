#pragma once

#include <string>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Reads the triangles of a Wavefront OBJ file.
///
/// Only `v x y z` and `f ...` lines are used (other statements such as vt, vn, o, g, s, usemtl
/// are ignored). Face corners may be written `i`, `i/t`, `i//n` or `i/t/n`; negative indices
/// count back from the last vertex defined so far; polygons are fan-triangulated from their first
/// corner, keeping the file's winding (counter-clockwise seen from outside by convention).
///
/// @param path file to read.
/// @param metres_per_unit size of the file's length unit [m/unit]; finite and > 0.
/// @return surface with vertices in metres (all `v` vertices, used or not).
/// @throws std::invalid_argument if metres_per_unit is not finite and > 0.
/// @throws std::runtime_error "path:line: what" for an unreadable file, a bad number, a face
///         with fewer than 3 corners, a vertex index of 0 or out of range, or a file without
///         faces.
TriMesh readObj(const std::string& path, double metres_per_unit);

/// Reads an STL file, ASCII or binary (little-endian; detected from the file size and the
/// leading "solid" keyword).
///
/// Vertices with exactly equal coordinates are welded into one vertex (in order of first
/// appearance). Triangles that collapse after welding (two equal corners) are dropped. Stored
/// facet normals are ignored; the winding of the file is kept.
///
/// @param path file to read.
/// @param metres_per_unit size of the file's length unit [m/unit]; finite and > 0.
/// @return surface with vertices in metres.
/// @throws std::invalid_argument if metres_per_unit is not finite and > 0.
/// @throws std::runtime_error "path:line: what" (ASCII) or "path: what" (binary) for an
///         unreadable file, a truncated binary file, a malformed facet, a bad or non-finite
///         number, or a file without triangles.
TriMesh readStl(const std::string& path, double metres_per_unit);

}  // namespace surgical_sim::core
