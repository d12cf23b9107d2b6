#include "surgical_sim/core/mesh/surface.h"

#include <algorithm>
#include <array>

#include "surgical_sim/core/mesh/tet_faces.h"

namespace surgical_sim::core {
namespace {

/// Local Tet10 mid-edge nodes on the face opposite corner f (Gmsh order, see ElementType).
std::array<int, 3> tet10FaceMidNodes(int local_face) {
  constexpr std::array<std::array<int, 3>, 4> kMidNodes{
      {{{5, 8, 9}}, {{6, 8, 7}}, {{4, 9, 7}}, {{4, 5, 6}}}};
  return kMidNodes.at(static_cast<std::size_t>(local_face));
}

}  // namespace

SurfaceMesh extractSurface(const TetMesh& mesh) {
  const TetFaceGroups groups = groupTetFaces(mesh);
  std::vector<TetFace> boundary;
  for (int g = 0; g < groups.numGroups(); ++g) {
    if (groups.group_offsets[g + 1] - groups.group_offsets[g] == 1) {
      boundary.push_back(groups.faces[groups.group_offsets[g]]);
    }
  }
  std::sort(boundary.begin(), boundary.end(), [](const TetFace& a, const TetFace& b) {
    return a.element != b.element ? a.element < b.element : a.local_face < b.local_face;
  });
  SurfaceMesh surface;
  surface.triangles.resize(3, static_cast<Eigen::Index>(boundary.size()));
  const bool quadratic = mesh.type == ElementType::Tet10;
  for (std::size_t t = 0; t < boundary.size(); ++t) {
    const TetFace& face = boundary[t];
    for (int k = 0; k < 3; ++k) {
      surface.triangles(k, static_cast<Eigen::Index>(t)) = face.nodes[k];
      surface.nodes.push_back(face.nodes[k]);
      if (quadratic) {
        surface.nodes.push_back(mesh.elements(tet10FaceMidNodes(face.local_face)[k], face.element));
      }
    }
  }
  std::sort(surface.nodes.begin(), surface.nodes.end());
  surface.nodes.erase(std::unique(surface.nodes.begin(), surface.nodes.end()), surface.nodes.end());
  return surface;
}

std::vector<int> nodesWhere(const TetMesh& mesh,
                            const std::function<bool(const Eigen::Vector3d&)>& pred) {
  std::vector<int> selected;
  for (int i = 0; i < mesh.numNodes(); ++i) {
    if (pred(mesh.nodes.col(i))) selected.push_back(i);
  }
  return selected;
}

}  // namespace surgical_sim::core
