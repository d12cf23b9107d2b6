#include "surgical_sim/core/tissue/tissue_mesh_check.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

/// Two tets; the second's apex moved to `height` [m] above the centroid of its base, the
/// equilateral triangle of side sqrt(2) m: 6 V / l_max^3 = sqrt(6) / 4 * height [1/m].
TetMesh withFlattenedSecondTet(double height) {
  TetMesh mesh = test::twoTets();
  const Eigen::Vector3d p0 = mesh.nodes.col(mesh.elements(0, 1));
  const Eigen::Vector3d p1 = mesh.nodes.col(mesh.elements(1, 1));
  const Eigen::Vector3d p2 = mesh.nodes.col(mesh.elements(2, 1));
  const Eigen::Vector3d normal = (p1 - p0).cross(p2 - p0).normalized();
  mesh.nodes.col(mesh.elements(3, 1)) = (p0 + p1 + p2) / 3.0 + height * normal;
  return mesh;
}

/// What checkTissueMesh() throws for `mesh` ("" when it passes).
std::string checkMessage(const TetMesh& mesh) {
  try {
    checkTissueMesh(mesh, "svk", true);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(TissueMeshCheck, SliverBelowTheShapeThresholdIsNamedDegenerate) {
  EXPECT_EQ(checkMessage(withFlattenedSecondTet(1e-9)), "");
  const std::string sliver = checkMessage(withFlattenedSecondTet(1e-11));
  EXPECT_NE(sliver.find("mesh.elements: element 1 is degenerate"), std::string::npos) << sliver;
  const std::string inverted = checkMessage(withFlattenedSecondTet(-0.1));
  EXPECT_NE(inverted.find("mesh.elements: element 1 is inverted"), std::string::npos) << inverted;
}

}  // namespace
}  // namespace surgical_sim::core
