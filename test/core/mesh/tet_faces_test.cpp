#include "surgical_sim/core/mesh/tet_faces.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include "two_tets.h"

namespace surgical_sim::core {
namespace {

TEST(TetFaceCorners, FacesPointAwayFromTheOppositeCorner) {
  Eigen::Matrix<double, 3, 4> corners;  // positively oriented unit corner tetrahedron
  corners << 0, 1, 0, 0,                //
      0, 0, 1, 0,                       //
      0, 0, 0, 1;
  for (int f = 0; f < 4; ++f) {
    const std::array<int, 3> face = tetFaceCorners(f);
    for (int k : face) EXPECT_NE(k, f);
    const Eigen::Vector3d a = corners.col(face[0]);
    const Eigen::Vector3d normal = (corners.col(face[1]) - a).cross(corners.col(face[2]) - a);
    EXPECT_LT(normal.dot(corners.col(f) - a), 0.0) << "face " << f;
  }
}

TEST(GroupTetFaces, SharedFaceFormsOneGroupOfTwo) {
  const TetMesh mesh = twoTets();
  const TetFaceGroups groups = groupTetFaces(mesh);
  ASSERT_EQ(groups.faces.size(), 8u);
  ASSERT_EQ(groups.numGroups(), 7);
  int shared = 0;
  for (int g = 0; g < groups.numGroups(); ++g) {
    const int size = groups.group_offsets[g + 1] - groups.group_offsets[g];
    if (size != 2) continue;
    ++shared;
    const TetFace& a = groups.faces[groups.group_offsets[g]];
    const TetFace& b = groups.faces[groups.group_offsets[g] + 1];
    EXPECT_EQ(a.element, 0);
    EXPECT_EQ(a.local_face, 0);  // opposite node 0
    EXPECT_EQ(b.element, 1);
    EXPECT_EQ(b.local_face, 3);  // opposite node 4
    // The two elements see the shared face with opposite windings.
    EXPECT_EQ(a.nodes, (std::array<int, 3>{1, 2, 3}));
    EXPECT_EQ(b.nodes, (std::array<int, 3>{1, 3, 2}));
  }
  EXPECT_EQ(shared, 1);
}

}  // namespace
}  // namespace surgical_sim::core
