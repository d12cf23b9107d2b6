#include "surgical_sim/core/mesh/mesh_check.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "surgical_sim/core/mesh/generators.h"
#include "two_tets.h"

namespace surgical_sim::core {
namespace {

std::vector<MeshIssue> issuesOfKind(const std::vector<MeshIssue>& issues, MeshIssueKind kind) {
  std::vector<MeshIssue> selected;
  std::copy_if(issues.begin(), issues.end(), std::back_inserter(selected),
               [kind](const MeshIssue& issue) { return issue.kind == kind; });
  return selected;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(SignedVolume, UnitCornerTetIsOneSixth) {
  const TetMesh mesh = twoTets();
  EXPECT_NEAR(signedVolume(mesh, 0), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(signedVolume(mesh, 1), 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(meshVolume(mesh), 0.5, 1e-15);
  EXPECT_THROW(signedVolume(mesh, 2), std::invalid_argument);
  EXPECT_THROW(signedVolume(mesh, -1), std::invalid_argument);
}

TEST(CheckMesh, ValidMeshesHaveNoIssues) {
  EXPECT_TRUE(checkMesh(twoTets()).empty());
  for (const double scale : {1e-3, 1.0, 1e3}) {
    const TetMesh mesh = makeOrganBlob(Eigen::Vector3d::Constant(scale), 6, ElementType::Tet10);
    EXPECT_TRUE(checkMesh(mesh).empty()) << "scale " << scale;
  }
}

TEST(CheckMesh, FindsInvertedElementByIndex) {
  TetMesh mesh = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3i(2, 2, 2),
                         ElementType::Tet4);
  std::swap(mesh.elements(1, 17), mesh.elements(2, 17));
  const std::vector<MeshIssue> issues = checkMesh(mesh);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].kind, MeshIssueKind::InvertedElement);
  EXPECT_TRUE(issues[0].is_error);
  EXPECT_EQ(issues[0].index, 17);
  // Each Kuhn tet of a 0.5 m cell has volume 0.125 / 6 = 0.0208 m^3.
  EXPECT_EQ(issues[0].message, "element 17 is inverted (signed volume -0.0208 m^3)");
  try {
    requireValidMesh(mesh);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(contains(e.what(), "1 errors: element 17 is inverted")) << e.what();
  }
}

TEST(CheckMesh, FindsDegenerateElementRelativeToItsSize) {
  for (const double scale : {1e-3, 1e3}) {
    TetMesh mesh = twoTets();
    mesh.nodes *= scale;
    mesh.nodes.col(4) = 0.5 * (mesh.nodes.col(1) + mesh.nodes.col(2));  // flat: in plane of 1,2,3
    const auto degenerate = issuesOfKind(checkMesh(mesh), MeshIssueKind::DegenerateElement);
    ASSERT_EQ(degenerate.size(), 1u) << "scale " << scale;
    EXPECT_EQ(degenerate[0].index, 1);
    EXPECT_TRUE(contains(degenerate[0].message, "element 1 is degenerate (signed volume"))
        << degenerate[0].message;
    EXPECT_THROW(requireValidMesh(mesh), std::invalid_argument);
  }
}

TEST(CheckMesh, FindsDuplicateNodes) {
  // The two tets do not share their common face: nodes 5, 6, 7 duplicate 1, 2, 3 (node 7 with
  // a 1e-12 m offset, below the 1e-9 * diagonal tolerance).
  TetMesh mesh = twoTets();
  mesh.nodes.conservativeResize(3, 8);
  mesh.nodes.col(5) = mesh.nodes.col(1);
  mesh.nodes.col(6) = mesh.nodes.col(2);
  mesh.nodes.col(7) = mesh.nodes.col(3) + Eigen::Vector3d(1e-12, 0.0, 0.0);
  mesh.elements.col(1) << 5, 6, 7, 4;
  const std::vector<MeshIssue> issues = checkMesh(mesh);
  const auto duplicates = issuesOfKind(issues, MeshIssueKind::DuplicateNode);
  ASSERT_EQ(duplicates.size(), 3u);
  ASSERT_EQ(issues.size(), 3u);
  std::vector<int> indices;
  for (const MeshIssue& issue : duplicates) indices.push_back(issue.index);
  std::sort(indices.begin(), indices.end());
  EXPECT_EQ(indices, (std::vector<int>{5, 6, 7}));
  for (const MeshIssue& issue : duplicates) {
    EXPECT_TRUE(contains(issue.message, "node " + std::to_string(issue.index) +
                                            " duplicates node " + std::to_string(issue.index - 4)))
        << issue.message;
  }
  // Nodes 1e-6 m apart in a 1.7 m mesh are distinct.
  mesh.nodes.col(5) += Eigen::Vector3d(0.0, 1e-6, 0.0);
  mesh.nodes.col(6) += Eigen::Vector3d(0.0, 0.0, 1e-6);
  mesh.nodes.col(7) += Eigen::Vector3d(1e-6, 0.0, 0.0);
  EXPECT_TRUE(checkMesh(mesh).empty());
}

TEST(CheckMesh, FindsNonManifoldFace) {
  // Three tets on face (1, 2, 3): elements 1 and 2 overlap on the same side.
  TetMesh mesh = twoTets();
  mesh.nodes.conservativeResize(3, 6);
  mesh.nodes.col(5) << 0.8, 0.9, 0.7;
  mesh.elements.conservativeResize(4, 3);
  mesh.elements.col(2) << 1, 2, 3, 5;
  const std::vector<MeshIssue> issues = checkMesh(mesh);
  const auto faces = issuesOfKind(issues, MeshIssueKind::NonManifoldFace);
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_EQ(faces[0].index, 0);
  EXPECT_TRUE(contains(faces[0].message, "is shared by 3 elements (0, 1, 2)")) << faces[0].message;
  EXPECT_THROW(requireValidMesh(mesh), std::invalid_argument);
}

TEST(CheckMesh, FindsNonManifoldSurfaceEdge) {
  // Two tets touching only along edge (0, 1): four surface triangles on that edge.
  TetMesh mesh;
  mesh.nodes.resize(3, 6);
  mesh.nodes << 0, 1, 0, 0, 0, 0,  //
      0, 0, 1, 0, -1, 0,           //
      0, 0, 0, 1, 0, -1;
  mesh.elements.resize(4, 2);
  mesh.elements << 0, 0, 1, 1, 2, 4, 3, 5;
  const auto edges = issuesOfKind(checkMesh(mesh), MeshIssueKind::NonManifoldEdge);
  ASSERT_EQ(edges.size(), 1u);
  EXPECT_EQ(edges[0].index, 0);
  EXPECT_EQ(edges[0].message, "surface edge (0, 1) has 4 surface triangles, expected 2");
}

TEST(CheckMesh, FindsIndexOutOfRangeAndRepeatedNodes) {
  TetMesh mesh = twoTets();
  mesh.elements(3, 1) = 99;
  std::vector<MeshIssue> issues = checkMesh(mesh);
  auto bad = issuesOfKind(issues, MeshIssueKind::IndexOutOfRange);
  ASSERT_EQ(bad.size(), 1u);
  EXPECT_EQ(bad[0].index, 1);
  EXPECT_TRUE(contains(bad[0].message, "element 1 references node 99")) << bad[0].message;
  // Node 4 is now unused: a warning, next to the error.
  const auto unused = issuesOfKind(issues, MeshIssueKind::UnreferencedNode);
  ASSERT_EQ(unused.size(), 1u);
  EXPECT_FALSE(unused[0].is_error);
  EXPECT_EQ(unused[0].index, 4);

  mesh.elements(3, 1) = -1;
  bad = issuesOfKind(checkMesh(mesh), MeshIssueKind::IndexOutOfRange);
  ASSERT_EQ(bad.size(), 1u);
  EXPECT_TRUE(contains(bad[0].message, "element 1 references node -1")) << bad[0].message;

  mesh.elements(3, 1) = 1;
  const auto repeated = issuesOfKind(checkMesh(mesh), MeshIssueKind::RepeatedNodeInElement);
  ASSERT_EQ(repeated.size(), 1u);
  EXPECT_EQ(repeated[0].index, 1);
  EXPECT_TRUE(contains(repeated[0].message, "element 1 lists node 1 twice")) << repeated[0].message;
  EXPECT_THROW(requireValidMesh(mesh), std::invalid_argument);
}

TEST(RequireValidMesh, WarningsDoNotThrow) {
  TetMesh mesh = twoTets();
  mesh.nodes.conservativeResize(3, 6);
  mesh.nodes.col(5) << 5.0, 5.0, 5.0;
  const std::vector<MeshIssue> issues = checkMesh(mesh);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].kind, MeshIssueKind::UnreferencedNode);
  EXPECT_EQ(issues[0].message, "node 5 is not used by any element");
  EXPECT_NO_THROW(requireValidMesh(mesh));
}

TEST(RequireValidMesh, ListsOnlyTheFirstErrors) {
  TetMesh mesh = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3i(2, 2, 2),
                         ElementType::Tet4);
  for (int e = 0; e < 10; ++e) std::swap(mesh.elements(1, e), mesh.elements(2, e));
  try {
    requireValidMesh(mesh);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_TRUE(contains(message, "10 errors: element 0 is inverted")) << message;
    EXPECT_TRUE(contains(message, "element 4 is inverted")) << message;
    EXPECT_FALSE(contains(message, "element 5 is inverted")) << message;
    EXPECT_TRUE(contains(message, "; ...")) << message;
  }
}

/// Node-major DOFs (all three axes) of the nodes with z <= z_max [m].
std::vector<int> dofsAtOrBelow(const TetMesh& mesh, double z_max) {
  std::vector<int> dofs;
  for (int i = 0; i < mesh.numNodes(); ++i)
    if (mesh.nodes(2, i) <= z_max)
      for (int a = 0; a < 3; ++a) dofs.push_back(3 * i + a);
  return dofs;
}

bool anyContains(const std::vector<std::string>& warnings, const std::string& text) {
  return std::any_of(warnings.begin(), warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

TEST(MeshWarnings, SaneHeldMeshHasNone) {
  const TetMesh box = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, 0.05, 0.03),
                              Eigen::Vector3i(4, 2, 2), ElementType::Tet4);
  EXPECT_TRUE(meshWarnings(box, dofsAtOrBelow(box, 0.0)).empty());
}

TEST(MeshWarnings, AbsurdScalesAreWarned) {
  // 200 m: a millimetre mesh read as metres; 0.1 mm: a metre mesh read as millimetres.
  const TetMesh huge = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(200.0),
                               Eigen::Vector3i::Ones(), ElementType::Tet4);
  const std::vector<std::string> big = meshWarnings(huge, dofsAtOrBelow(huge, 0.0));
  ASSERT_EQ(big.size(), 1u);
  EXPECT_NE(big[0].find("diagonal is 346 m, above 100 m"), std::string::npos) << big[0];
  const TetMesh tiny = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(1e-4),
                               Eigen::Vector3i::Ones(), ElementType::Tet4);
  const std::vector<std::string> small = meshWarnings(tiny, dofsAtOrBelow(tiny, 0.0));
  ASSERT_EQ(small.size(), 1u);
  EXPECT_NE(small[0].find("below 0.001 m"), std::string::npos) << small[0];
}

TEST(MeshWarnings, PieceWithoutFixedNodeIsWarned) {
  // Two separate unit-cell boxes (8 nodes, 5 tets each), the second 1 m above the first.
  const TetMesh lower = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.1),
                                Eigen::Vector3i::Ones(), ElementType::Tet4);
  TetMesh two;
  two.nodes.resize(3, 2 * lower.numNodes());
  two.nodes << lower.nodes, lower.nodes.colwise() + Eigen::Vector3d(0.0, 0.0, 1.0);
  two.elements.resize(4, 2 * lower.numElements());
  two.elements << lower.elements, lower.elements.array() + lower.numNodes();
  ASSERT_NO_THROW(requireValidMesh(two));

  const std::vector<std::string> one_free = meshWarnings(two, dofsAtOrBelow(two, 0.0));
  ASSERT_EQ(one_free.size(), 1u);
  EXPECT_NE(one_free[0].find("piece with 8 nodes and 5 elements (lowest node 8)"),
            std::string::npos)
      << one_free[0];
  EXPECT_TRUE(anyContains(one_free, "has no fixed node"));
  EXPECT_EQ(meshWarnings(two, {}).size(), 2u);
  EXPECT_TRUE(meshWarnings(two, dofsAtOrBelow(two, 1.0)).empty());
}

}  // namespace
}  // namespace surgical_sim::core
