#include "surgical_sim/core/cutting/cut_mesh_check.h"

#include <utility>

#include <gtest/gtest.h>

#include "surgical_sim/core/mesh/generators.h"

namespace surgical_sim::core {
namespace {

TEST(CutMeshCheck, ReportsABrokenMesh) {
  TetMesh mesh = makeBeam(1, 1, 1, Eigen::Vector3i(1, 1, 1), ElementType::Tet4);
  EXPECT_EQ(cutMeshProblem(mesh), "");
  std::swap(mesh.elements(0, 0), mesh.elements(1, 0));  // inverted
  EXPECT_NE(cutMeshProblem(mesh), "");
  TetMesh open = makeBeam(1, 1, 1, Eigen::Vector3i(1, 1, 1), ElementType::Tet4);
  open.elements.conservativeResize(4, 5);
  EXPECT_EQ(cutMeshProblem(open), "");  // removing an element keeps the surface closed
}

}  // namespace
}  // namespace surgical_sim::core
