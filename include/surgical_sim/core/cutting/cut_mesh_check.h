#pragma once

#include <string>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// First problem of a cut (virtual-node) mesh, or "" if none: an element that is inverted,
/// degenerate, out of range or repeats a node, a face shared by more than two elements, or an
/// open or inconsistently oriented surface edge. Duplicate rest nodes are expected after a cut
/// and pinched crack-front edges are allowed (see TetCutter).
std::string cutMeshProblem(const TetMesh& mesh);

}  // namespace surgical_sim::core
