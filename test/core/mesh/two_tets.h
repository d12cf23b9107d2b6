#pragma once

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Unit corner tetrahedron (nodes 0..3) plus node 4 = (1,1,1) beyond its slanted face: two Tet4
/// elements sharing the face (1, 2, 3).
inline TetMesh twoTets() {
  TetMesh mesh;
  mesh.nodes.resize(3, 5);
  mesh.nodes << 0, 1, 0, 0, 1,  //
      0, 0, 1, 0, 1,            //
      0, 0, 0, 1, 1;
  mesh.elements.resize(4, 2);
  mesh.elements << 0, 1, 1, 2, 2, 3, 3, 4;
  return mesh;
}

}  // namespace surgical_sim::core
