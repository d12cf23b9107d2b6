#include "surgical_sim/core/mesh/generators.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "surgical_sim/core/mesh/mesh_check.h"

namespace surgical_sim::core {
namespace {

double minElementVolume(const TetMesh& mesh) {
  double smallest = INFINITY;
  for (int e = 0; e < mesh.numElements(); ++e) smallest = std::min(smallest, signedVolume(mesh, e));
  return smallest;
}

void expectInvalidArgument(const std::function<void()>& make, const std::string& message) {
  try {
    make();
    FAIL() << "expected std::invalid_argument: " << message;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(MakeBox, VolumeCountsAndOrientation) {
  const Eigen::Vector3d min_corner(-1.0, 2.0, 0.5);
  const Eigen::Vector3d size(0.3, 0.2, 0.1);
  const TetMesh mesh = makeBox(min_corner, size, Eigen::Vector3i(3, 4, 5), ElementType::Tet4);
  EXPECT_EQ(mesh.numNodes(), 4 * 5 * 6);
  EXPECT_EQ(mesh.numElements(), 6 * 3 * 4 * 5);
  EXPECT_NEAR(meshVolume(mesh), 0.3 * 0.2 * 0.1, 1e-12 * 0.006);
  // Kuhn split: every tet of a cell has 1/6 of the cell volume.
  EXPECT_NEAR(minElementVolume(mesh), 0.006 / 60.0 / 6.0, 1e-15);
  EXPECT_TRUE(mesh.nodes.rowwise().minCoeff().isApprox(min_corner));
  EXPECT_TRUE(mesh.nodes.rowwise().maxCoeff().isApprox(min_corner + size));
  EXPECT_NO_THROW(requireValidMesh(mesh));
}

TEST(MakeBox, ValidAtMillimetreAndKilometreScales) {
  for (const double scale : {1e-3, 1e3}) {
    const TetMesh mesh = makeBox(Eigen::Vector3d::Constant(scale), Eigen::Vector3d::Constant(scale),
                                 Eigen::Vector3i(2, 3, 2), ElementType::Tet10);
    EXPECT_NO_THROW(requireValidMesh(mesh)) << "scale " << scale;
    EXPECT_NEAR(meshVolume(mesh), scale * scale * scale, 1e-12 * scale * scale * scale);
  }
}

TEST(MakeBeam, SpansDocumentedBoundsWithAnalyticVolume) {
  for (const ElementType type : {ElementType::Tet4, ElementType::Tet10}) {
    const TetMesh mesh = makeBeam(0.1, 0.02, 0.01, Eigen::Vector3i(10, 2, 1), type);
    EXPECT_EQ(mesh.type, type);
    EXPECT_TRUE(mesh.nodes.rowwise().minCoeff().isApprox(Eigen::Vector3d(0.0, -0.01, -0.005)));
    EXPECT_TRUE(mesh.nodes.rowwise().maxCoeff().isApprox(Eigen::Vector3d(0.1, 0.01, 0.005)));
    EXPECT_NEAR(meshVolume(mesh), 0.1 * 0.02 * 0.01, 1e-12 * 2e-5);
    EXPECT_GT(minElementVolume(mesh), 0.0);
    EXPECT_NO_THROW(requireValidMesh(mesh));
  }
}

TEST(MakeHexagonalBeam, CrossSectionAreaIsExactlyTheHexagon) {
  const double side = 0.013;
  const double length = 0.2;
  for (int rings = 1; rings <= 4; ++rings) {
    const TetMesh mesh = makeHexagonalBeam(side, length, 7, rings, ElementType::Tet4);
    EXPECT_EQ(mesh.numNodes(), (1 + 3 * rings * (rings + 1)) * 8);
    EXPECT_EQ(mesh.numElements(), 18 * rings * rings * 7);
    const double exact = 3.0 * std::sqrt(3.0) / 2.0 * side * side * length;
    EXPECT_NEAR(meshVolume(mesh), exact, 1e-12 * exact) << "rings " << rings;
    EXPECT_GT(minElementVolume(mesh), 0.0);
    EXPECT_NO_THROW(requireValidMesh(mesh));
    // Corners at (y, z) = side (cos 60 s, sin 60 s): flat sides at z = +-side sqrt(3)/2.
    EXPECT_NEAR(mesh.nodes.row(1).maxCoeff(), side, 1e-15);
    EXPECT_NEAR(mesh.nodes.row(2).maxCoeff(), side * std::sqrt(3.0) / 2.0, 1e-15);
    EXPECT_NEAR(mesh.nodes.row(0).maxCoeff(), length, 1e-15);
    EXPECT_NEAR(mesh.nodes.row(0).minCoeff(), 0.0, 1e-15);
  }
}

TEST(MakeHexagonalBeam, Tet10IsValid) {
  const TetMesh mesh = makeHexagonalBeam(0.01, 0.05, 3, 2, ElementType::Tet10);
  EXPECT_EQ(mesh.type, ElementType::Tet10);
  EXPECT_NO_THROW(requireValidMesh(mesh));
}

TEST(MakeOrganBlob, ElementQualityDoesNotDegradeWithRefinement) {
  // The plain cube-to-sphere map is singular at the cube corners and inverts elements there
  // from about 24 cells per axis; the generator's map keeps the smallest element volume a fixed
  // fraction of the mean at every resolution, odd or even.
  const Eigen::Vector3d semi_axes(0.075, 0.05, 0.03);
  for (const int cells : {1, 2, 3, 4, 5, 8, 13, 24, 31, 40}) {
    const TetMesh mesh = makeOrganBlob(semi_axes, cells, ElementType::Tet4);
    EXPECT_EQ(mesh.numNodes(), (cells + 1) * (cells + 1) * (cells + 1));
    EXPECT_EQ(mesh.numElements(), 6 * cells * cells * cells);
    const double mean_volume = meshVolume(mesh) / mesh.numElements();
    EXPECT_GT(minElementVolume(mesh), 0.25 * mean_volume) << "cells " << cells;
    if (cells <= 13) {
      EXPECT_NO_THROW(requireValidMesh(mesh)) << "cells " << cells;
    }
  }
}

TEST(MakeOrganBlob, VolumeConvergesToMappedBallVolume) {
  // The shape map has Jacobian determinant 0.8 - 0.2 u_x on the unit ball, whose odd part
  // integrates to zero: V = 0.8 (4/3) pi a b c.
  const Eigen::Vector3d semi_axes(0.075, 0.05, 0.03);
  const double exact = 0.8 * 4.0 / 3.0 * std::acos(-1.0) * semi_axes.prod();
  const double coarse = meshVolume(makeOrganBlob(semi_axes, 8, ElementType::Tet4));
  const double fine = meshVolume(makeOrganBlob(semi_axes, 16, ElementType::Tet4));
  EXPECT_LT(fine, exact);  // inscribed polyhedron of a convex-ish smooth body
  EXPECT_LT(std::abs(fine - exact), std::abs(coarse - exact));
  EXPECT_LT(std::abs(fine - exact) / exact, 0.03);
}

TEST(MakeOrganBlob, IsAsymmetricLikeALobe) {
  const TetMesh mesh = makeOrganBlob(Eigen::Vector3d(0.075, 0.05, 0.03), 10, ElementType::Tet4);
  double thickness_left = 0.0;   // max |z| over x < -a/2
  double thickness_right = 0.0;  // max |z| over x > +a/2
  for (int i = 0; i < mesh.numNodes(); ++i) {
    const Eigen::Vector3d p = mesh.nodes.col(i);
    if (p.x() < -0.0375) thickness_left = std::max(thickness_left, std::abs(p.z()));
    if (p.x() > 0.0375) thickness_right = std::max(thickness_right, std::abs(p.z()));
  }
  EXPECT_GT(thickness_left, 1.3 * thickness_right);
  EXPECT_LE(mesh.nodes.row(2).cwiseAbs().maxCoeff(), 0.03 + 1e-12);
}

TEST(MakeOrganBlob, Tet10MidNodesFollowTheCurvedShape) {
  const TetMesh mesh = makeOrganBlob(Eigen::Vector3d(0.075, 0.05, 0.03), 4, ElementType::Tet10);
  EXPECT_EQ(mesh.type, ElementType::Tet10);
  EXPECT_NO_THROW(requireValidMesh(mesh));
  // Mapped mid-edge nodes are not all at straight midpoints.
  double max_offset = 0.0;
  for (int e = 0; e < mesh.numElements(); ++e) {
    const Eigen::Vector3d mid =
        0.5 * (mesh.nodes.col(mesh.elements(0, e)) + mesh.nodes.col(mesh.elements(1, e)));
    max_offset = std::max(max_offset, (mesh.nodes.col(mesh.elements(4, e)) - mid).norm());
  }
  EXPECT_GT(max_offset, 1e-4);
}

TEST(PromoteToTet10, MidNodesAtEdgeMidpointsAndShared) {
  const TetMesh tet4 = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 2.0, 3.0),
                               Eigen::Vector3i(2, 2, 2), ElementType::Tet4);
  const TetMesh tet10 = promoteToTet10(tet4);
  ASSERT_EQ(tet10.type, ElementType::Tet10);
  ASSERT_EQ(tet10.numElements(), tet4.numElements());
  EXPECT_EQ(tet10.elements.topRows(4), tet4.elements);
  EXPECT_EQ(tet10.nodes.leftCols(tet4.numNodes()), tet4.nodes);
  const int edges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
  std::map<std::pair<int, int>, int> edge_node;
  for (int e = 0; e < tet10.numElements(); ++e) {
    for (int m = 0; m < 6; ++m) {
      const int p = tet10.elements(edges[m][0], e);
      const int q = tet10.elements(edges[m][1], e);
      const int mid = tet10.elements(4 + m, e);
      EXPECT_TRUE(tet10.nodes.col(mid).isApprox(0.5 * (tet10.nodes.col(p) + tet10.nodes.col(q))));
      const auto inserted = edge_node.emplace(std::make_pair(std::min(p, q), std::max(p, q)), mid);
      EXPECT_EQ(inserted.first->second, mid) << "edge (" << p << ", " << q << ") not shared";
    }
  }
  // One node per unique edge, no more.
  EXPECT_EQ(tet10.numNodes(), tet4.numNodes() + static_cast<int>(edge_node.size()));
  EXPECT_NO_THROW(requireValidMesh(tet10));
}

TEST(PromoteToTet10, RejectsTet10AndBadIndices) {
  const TetMesh tet4 = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
                               Eigen::Vector3i(1, 1, 1), ElementType::Tet4);
  expectInvalidArgument([&] { promoteToTet10(promoteToTet10(tet4)); },
                        "promoteToTet10: mesh type is tet10, expected tet4");
  TetMesh broken = tet4;
  broken.elements(2, 3) = 8;
  expectInvalidArgument([&] { promoteToTet10(broken); },
                        "promoteToTet10: element 3 references node 8 but the mesh has 8 nodes");
}

TEST(Generators, ValidatorsNameTheParameter) {
  const Eigen::Vector3i cells(2, 2, 2);
  expectInvalidArgument(
      [&] { makeBeam(1.0, 0.1, 0.1, Eigen::Vector3i(0, 1, 1), ElementType::Tet4); },
      "makeBeam: cells.x = 0 must be >= 1");
  expectInvalidArgument([&] { makeBeam(-1.0, 0.1, 0.1, cells, ElementType::Tet4); },
                        "makeBeam: length = -1 m");
  expectInvalidArgument([&] { makeBeam(1.0, 0.1, NAN, cells, ElementType::Tet4); },
                        "makeBeam: height");
  expectInvalidArgument(
      [&] {
        makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.0, 1.0), cells, ElementType::Tet4);
      },
      "makeBox: size.y = 0 m");
  expectInvalidArgument(
      [&] {
        makeBox(Eigen::Vector3d(0.0, 0.0, INFINITY), Eigen::Vector3d::Ones(), cells,
                ElementType::Tet4);
      },
      "makeBox: min_corner.z");
  expectInvalidArgument(
      [&] {
        makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3i(1, 1, -2),
                ElementType::Tet4);
      },
      "makeBox: cells.z = -2 must be >= 1");
  expectInvalidArgument([&] { makeHexagonalBeam(0.0, 1.0, 1, 1, ElementType::Tet4); },
                        "makeHexagonalBeam: side = 0 m");
  expectInvalidArgument([&] { makeHexagonalBeam(1.0, 1.0, 0, 1, ElementType::Tet4); },
                        "makeHexagonalBeam: cells_along = 0 must be >= 1");
  expectInvalidArgument([&] { makeHexagonalBeam(1.0, 1.0, 1, 0, ElementType::Tet4); },
                        "makeHexagonalBeam: rings = 0 must be >= 1");
  expectInvalidArgument(
      [&] { makeOrganBlob(Eigen::Vector3d(1.0, 1.0, -1.0), 4, ElementType::Tet4); },
      "makeOrganBlob: semi_axes.z = -1 m");
  expectInvalidArgument([&] { makeOrganBlob(Eigen::Vector3d::Ones(), 0, ElementType::Tet4); },
                        "makeOrganBlob: cells_per_axis = 0 must be >= 1");
  expectInvalidArgument([&] { makeBeam(1.0, 0.1, 0.1, cells, static_cast<ElementType>(3)); },
                        "makeBeam: type = 3 is not a known ElementType");
}

}  // namespace
}  // namespace surgical_sim::core
