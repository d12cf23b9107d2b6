#pragma once

#include <string>
#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Kinds of problems found by checkMesh().
enum class MeshIssueKind {
  IndexOutOfRange,        ///< element references a node index < 0 or >= numNodes() (error)
  RepeatedNodeInElement,  ///< an element lists the same node twice (error)
  InvertedElement,        ///< negative signed volume (error)
  DegenerateElement,      ///< |signed volume| < 1e-12 (mean edge length)^3, or non-finite (error)
  DuplicateNode,          ///< two nodes closer than 1e-9 bounding-box diagonal (error)
  UnreferencedNode,       ///< node used by no element (warning)
  NonManifoldEdge,        ///< surface edge with a number of surface triangles other than 2 (error)
  NonManifoldFace,        ///< face shared by more than 2 elements (error)
};

/// One problem found by checkMesh().
struct MeshIssue {
  MeshIssueKind kind;
  bool is_error;        ///< false for warnings (requireValidMesh() ignores them)
  int index;            ///< element index for element issues and NonManifoldFace (lowest
                        ///< element), node index for node issues (the higher index of a
                        ///< duplicate pair), lower node index for NonManifoldEdge
  std::string message;  ///< names the index and the offending value, e.g.
                        ///< "element 17 is inverted (signed volume -3.2e-09 m^3)"
};

/// Signed volume of an element from its 4 corner nodes [m^3]:
/// det[x1 - x0, x2 - x0, x3 - x0] / 6, positive for a positively oriented element.
/// @throws std::invalid_argument if element is out of range (node indices are not checked).
double signedVolume(const TetMesh& mesh, int element);

/// Sum of signed corner volumes of all elements [m^3] (straight-sided volume for Tet10).
double meshVolume(const TetMesh& mesh);

/// Checks a mesh and lists every problem found: index range, repeated nodes, inverted and
/// degenerate elements, duplicate and unreferenced nodes, non-manifold faces and surface edges.
/// Geometric checks skip elements with bad indices, and the topological checks (faces, edges)
/// run only when all indices are in range. Runs in O(m log m + n) time.
std::vector<MeshIssue> checkMesh(const TetMesh& mesh);

/// Bounding-box diagonals outside [kMinPlausibleMeshDiagonal, kMaxPlausibleMeshDiagonal] get a
/// scale warning from meshWarnings(): a soft-tissue mesh in metres is millimetres to metres
/// across, so such a mesh was most likely read with the wrong length unit.
constexpr double kMinPlausibleMeshDiagonal = 1e-3;   ///< [m]
constexpr double kMaxPlausibleMeshDiagonal = 100.0;  ///< [m]

/// Warnings (not errors) about a mesh that passes requireValidMesh() but is probably not what
/// the scene intended, one message per problem:
///  - the bounding-box diagonal is outside [kMinPlausibleMeshDiagonal,
///    kMaxPlausibleMeshDiagonal] (message names the diagonal in m and the likely unit mistake);
///  - a connected piece of the mesh (elements sharing nodes) has no node with a fixed DOF, so it
///    floats freely: in a dynamic scene it falls or drifts as a rigid body, in a quasi-static one
///    its stiffness is singular (message names the piece's node and element counts and one of
///    its nodes). At most 5 pieces are listed, then a count of the rest.
/// @param mesh mesh in metres with node indices in range.
/// @param fixed_dofs node-major DOF indices (3 node + axis) held fixed; out-of-range entries
///        are ignored.
/// @return warnings, empty for a sane mesh with every piece held.
std::vector<std::string> meshWarnings(const TetMesh& mesh, const std::vector<int>& fixed_dofs);

/// Runs checkMesh() and throws if it finds an error (warnings pass).
/// @throws std::invalid_argument "invalid mesh: N errors: <first 5 messages>".
void requireValidMesh(const TetMesh& mesh);

}  // namespace surgical_sim::core
