#include "surgical_sim/core/mesh/surface.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/gmsh_reader.h"
#include "surgical_sim/core/mesh/mesh_check.h"
#include "two_tets.h"

namespace surgical_sim::core {
namespace {

/// Number of surface triangles on each undirected edge.
std::map<std::pair<int, int>, int> edgeTriangleCounts(const SurfaceMesh& surface) {
  std::map<std::pair<int, int>, int> counts;
  for (int t = 0; t < surface.triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = surface.triangles(k, t);
      const int b = surface.triangles((k + 1) % 3, t);
      ++counts[{std::min(a, b), std::max(a, b)}];
    }
  }
  return counts;
}

/// Divergence theorem: V = sum over triangles of (centroid . normal) area / 3 [m^3].
double divergenceVolume(const TetMesh& mesh, const SurfaceMesh& surface) {
  double volume = 0.0;
  for (int t = 0; t < surface.triangles.cols(); ++t) {
    const Eigen::Vector3d a = mesh.nodes.col(surface.triangles(0, t));
    const Eigen::Vector3d b = mesh.nodes.col(surface.triangles(1, t));
    const Eigen::Vector3d c = mesh.nodes.col(surface.triangles(2, t));
    const Eigen::Vector3d area_normal = 0.5 * (b - a).cross(c - a);
    volume += ((a + b + c) / 3.0).dot(area_normal) / 3.0;
  }
  return volume;
}

/// Checks a closed, outward, sphere-like surface: every edge has 2 triangles, Euler
/// characteristic V - E + F = 2, and the divergence theorem gives the mesh volume.
void expectClosedOutwardSphere(const TetMesh& mesh, const std::string& label) {
  const SurfaceMesh surface = extractSurface(mesh);
  const auto edges = edgeTriangleCounts(surface);
  for (const auto& [edge, count] : edges) {
    ASSERT_EQ(count, 2) << label << ": edge (" << edge.first << ", " << edge.second << ")";
  }
  std::set<int> corner_nodes(surface.triangles.data(),
                             surface.triangles.data() + surface.triangles.size());
  const int euler = static_cast<int>(corner_nodes.size()) - static_cast<int>(edges.size()) +
                    static_cast<int>(surface.triangles.cols());
  EXPECT_EQ(euler, 2) << label;
  const double volume = meshVolume(mesh);
  EXPECT_NEAR(divergenceVolume(mesh, surface), volume, 1e-12 * volume) << label;
}

TEST(ExtractSurface, GeneratedMeshesHaveClosedOutwardSurfaces) {
  expectClosedOutwardSphere(
      makeBox(Eigen::Vector3d(-0.1, 0.0, 0.3), Eigen::Vector3d(0.2, 0.1, 0.05),
              Eigen::Vector3i(4, 3, 2), ElementType::Tet4),
      "box");
  expectClosedOutwardSphere(
      makeBeam(0.1, 0.01, 0.01, Eigen::Vector3i(10, 2, 2), ElementType::Tet10), "tet10 beam");
  expectClosedOutwardSphere(makeHexagonalBeam(0.01, 0.1, 5, 3, ElementType::Tet4), "hex beam");
  expectClosedOutwardSphere(makeOrganBlob(Eigen::Vector3d(0.075, 0.05, 0.03), 8, ElementType::Tet4),
                            "organ blob");
  expectClosedOutwardSphere(
      readGmsh(std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/meshes/liver_lobe.msh", 1e-3),
      "liver lobe");
}

TEST(ExtractSurface, BoxSurfaceHasTwoTrianglesPerCellFace) {
  const Eigen::Vector3i cells(4, 3, 2);
  const TetMesh mesh =
      makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d(4.0, 3.0, 2.0), cells, ElementType::Tet4);
  const SurfaceMesh surface = extractSurface(mesh);
  EXPECT_EQ(surface.triangles.cols(), 2 * 2 * (4 * 3 + 3 * 2 + 2 * 4));
  // Outward: every triangle on the face x = 4 has a normal along +x.
  for (int t = 0; t < surface.triangles.cols(); ++t) {
    const Eigen::Vector3d a = mesh.nodes.col(surface.triangles(0, t));
    const Eigen::Vector3d b = mesh.nodes.col(surface.triangles(1, t));
    const Eigen::Vector3d c = mesh.nodes.col(surface.triangles(2, t));
    if (a.x() == 4.0 && b.x() == 4.0 && c.x() == 4.0) {
      EXPECT_GT((b - a).cross(c - a).x(), 0.0);
    }
  }
}

TEST(ExtractSurface, SurfaceNodesAreTheBoundaryNodesIncludingTet10MidNodes) {
  for (const ElementType type : {ElementType::Tet4, ElementType::Tet10}) {
    const TetMesh mesh =
        makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3i(3, 3, 3), type);
    const SurfaceMesh surface = extractSurface(mesh);
    const auto on_boundary = [](const Eigen::Vector3d& p) {
      return (p.array() < 1e-12).any() || (p.array() > 1.0 - 1e-12).any();
    };
    EXPECT_EQ(surface.nodes, nodesWhere(mesh, on_boundary)) << toString(type);
  }
}

TEST(ExtractSurface, InteriorFaceOfTwoTetsIsRemoved) {
  const TetMesh mesh = twoTets();
  const SurfaceMesh surface = extractSurface(mesh);
  EXPECT_EQ(surface.triangles.cols(), 6);
  EXPECT_EQ(surface.nodes, (std::vector<int>{0, 1, 2, 3, 4}));
  for (int t = 0; t < surface.triangles.cols(); ++t) {
    std::set<int> face(surface.triangles.col(t).data(), surface.triangles.col(t).data() + 3);
    EXPECT_NE(face, (std::set<int>{1, 2, 3}));
  }
  EXPECT_NEAR(divergenceVolume(mesh, surface), 0.5, 1e-15);
}

TEST(NodesWhere, ReturnsSortedMatchingNodes) {
  const TetMesh mesh = makeBeam(1.0, 0.1, 0.1, Eigen::Vector3i(5, 2, 3), ElementType::Tet4);
  const std::vector<int> clamped =
      nodesWhere(mesh, [](const Eigen::Vector3d& p) { return p.x() < 1e-9; });
  EXPECT_EQ(clamped.size(), 3u * 4u);
  EXPECT_TRUE(std::is_sorted(clamped.begin(), clamped.end()));
  for (int i : clamped) EXPECT_EQ(mesh.nodes(0, i), 0.0);
  EXPECT_TRUE(nodesWhere(mesh, [](const Eigen::Vector3d& p) { return p.x() > 2.0; }).empty());
}

}  // namespace
}  // namespace surgical_sim::core
