#pragma once

#include <array>
#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// One triangular face of a tetrahedron (corner nodes only).
struct TetFace {
  std::array<int, 3> nodes;  ///< volume node indices, counter-clockwise seen from outside the
                             ///< element (outward for a positively oriented element)
  int element;               ///< element index
  int local_face;            ///< 0..3: the face opposite local corner local_face
};

/// All faces of all elements, grouped so that coincident faces (same three nodes, any order)
/// are consecutive. A face in a group of size 1 is on the boundary, size 2 is interior, larger
/// is non-manifold.
struct TetFaceGroups {
  std::vector<TetFace> faces;      ///< 4 numElements() faces, sorted by their node set, then by
                                   ///< element and local face
  std::vector<int> group_offsets;  ///< group g is faces[group_offsets[g], group_offsets[g+1]),
                                   ///< size numGroups() + 1
  int numGroups() const { return static_cast<int>(group_offsets.size()) - 1; }
};

/// Local corners of the face opposite corner f (f = 0..3), ordered counter-clockwise seen from
/// outside a positively oriented element: {1,2,3}, {0,3,2}, {0,1,3}, {0,2,1}.
/// local_face must be in 0..3 (unchecked: hot in cutting).
inline std::array<int, 3> tetFaceCorners(int local_face) {
  constexpr std::array<std::array<int, 3>, 4> kFaces{
      {{{1, 2, 3}}, {{0, 3, 2}}, {{0, 1, 3}}, {{0, 2, 1}}}};
  return kFaces[static_cast<std::size_t>(local_face)];
}

/// Groups the faces of all elements of the mesh (O(m log m)).
/// @param mesh mesh whose corner node indices are all in range (see checkMesh()).
TetFaceGroups groupTetFaces(const TetMesh& mesh);

}  // namespace surgical_sim::core
