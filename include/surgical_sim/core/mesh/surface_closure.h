#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Edge census of a triangle surface.
struct SurfaceClosure {
  int open_edges = 0;     ///< undirected edges whose two directions are used a different number
                          ///< of times (a hole or an inconsistently oriented triangle); 0 iff the
                          ///< surface is closed and consistently oriented
  int pinched_edges = 0;  ///< edges with more than 2 triangles (not edge-manifold), e.g. the front
                          ///< of a partial cut, where the two lips of the crack meet
};

/// Counts open and pinched edges of the triangles (vertex indices, shape 3 x t), O(t log t).
SurfaceClosure checkSurfaceClosure(const Eigen::Matrix3Xi& triangles);

}  // namespace surgical_sim::core
