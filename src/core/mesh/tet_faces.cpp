#include "surgical_sim/core/mesh/tet_faces.h"

#include <algorithm>

namespace surgical_sim::core {
namespace {

std::array<int, 3> sortedNodes(const TetFace& face) {
  std::array<int, 3> key = face.nodes;
  std::sort(key.begin(), key.end());
  return key;
}

}  // namespace

TetFaceGroups groupTetFaces(const TetMesh& mesh) {
  struct KeyedFace {
    std::array<int, 3> key;
    TetFace face;
  };
  std::vector<KeyedFace> keyed;
  keyed.reserve(4 * static_cast<std::size_t>(mesh.numElements()));
  for (int e = 0; e < mesh.numElements(); ++e) {
    for (int f = 0; f < 4; ++f) {
      const std::array<int, 3> corners = tetFaceCorners(f);
      TetFace face{{mesh.elements(corners[0], e), mesh.elements(corners[1], e),
                    mesh.elements(corners[2], e)},
                   e,
                   f};
      keyed.push_back({sortedNodes(face), face});
    }
  }
  std::sort(keyed.begin(), keyed.end(), [](const KeyedFace& a, const KeyedFace& b) {
    if (a.key != b.key) return a.key < b.key;
    if (a.face.element != b.face.element) return a.face.element < b.face.element;
    return a.face.local_face < b.face.local_face;
  });
  TetFaceGroups groups;
  groups.faces.reserve(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].key != keyed[i - 1].key) {
      groups.group_offsets.push_back(static_cast<int>(i));
    }
    groups.faces.push_back(keyed[i].face);
  }
  groups.group_offsets.push_back(static_cast<int>(keyed.size()));
  return groups;
}

}  // namespace surgical_sim::core
