#pragma once

#include <string>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Configuration-time validation of a mesh handed to a tissue model.
/// Checks: at least one element; elements has 4 (Tet4) / 10 (Tet10) rows; node indices in
/// [0, numNodes()); node coordinates finite; every element's corner tetrahedron positively
/// oriented and non-degenerate (6 V / l_max^3 > 1e-10, V the signed corner volume [m^3], l_max
/// the longest corner edge [m]).
/// @param model tissue model name used in the messages, e.g. "mass_spring".
/// @param allow_tet10 false for models that only support linear tetrahedra.
/// @throws std::invalid_argument naming "mesh.elements" and the element index, or the model and
///         the element type when Tet10 is not supported.
void checkTissueMesh(const TetMesh& mesh, const std::string& model, bool allow_tet10);

/// Signed volume [m^3] of the tetrahedron with corners p0..p3 [m] (positive when p1-p0, p2-p0,
/// p3-p0 form a right-handed triad).
double signedTetVolume(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                       const Eigen::Vector3d& p2, const Eigen::Vector3d& p3);

}  // namespace surgical_sim::core
