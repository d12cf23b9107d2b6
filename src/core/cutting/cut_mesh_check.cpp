#include "surgical_sim/core/cutting/cut_mesh_check.h"

#include "surgical_sim/core/mesh/mesh_check.h"
#include "surgical_sim/core/mesh/surface.h"
#include "surgical_sim/core/mesh/surface_closure.h"

namespace surgical_sim::core {

std::string cutMeshProblem(const TetMesh& mesh) {
  for (const MeshIssue& issue : checkMesh(mesh))
    if (issue.is_error && issue.kind != MeshIssueKind::DuplicateNode &&
        issue.kind != MeshIssueKind::NonManifoldEdge)
      return issue.message;
  const SurfaceClosure closure = checkSurfaceClosure(extractSurface(mesh).triangles);
  if (closure.open_edges > 0) return std::to_string(closure.open_edges) + " open surface edges";
  return "";
}

}  // namespace surgical_sim::core
