#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Boundary surface of a tetrahedral mesh, expressed in the volume mesh's node indices.
struct SurfaceMesh {
  Eigen::Matrix3Xi triangles;  ///< volume corner node indices, shape 3 x t, counter-clockwise
                               ///< seen from outside (outward for positively oriented elements)
  std::vector<int> nodes;      ///< sorted unique volume nodes on the surface (for Tet10 also the
                               ///< mid-edge nodes of surface triangles)
};

/// Extracts the faces that belong to exactly one element, oriented outward, in order of
/// (element, local face). Faces shared by more than two elements (non-manifold) are not surface.
/// @param mesh mesh with node indices in range (see checkMesh()).
SurfaceMesh extractSurface(const TetMesh& mesh);

/// Indices of the nodes whose position p_M [m] (mesh frame) satisfies pred, in increasing order.
/// Typical use: boundary conditions, e.g. nodesWhere(mesh, [](auto& p) { return p.x() < 1e-9; }).
std::vector<int> nodesWhere(const TetMesh& mesh,
                            const std::function<bool(const Eigen::Vector3d&)>& pred);

}  // namespace surgical_sim::core
