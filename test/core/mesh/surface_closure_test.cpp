#include <gtest/gtest.h>

#include "surgical_sim/core/mesh/surface_closure.h"

namespace surgical_sim::core {
namespace {

Eigen::Matrix3Xi tetSurface(int a, int b, int c, int d) {
  Eigen::Matrix3Xi t(3, 4);
  t << b, a, a, a,  //
      c, d, b, c,   //
      d, c, d, b;
  return t;
}

TEST(SurfaceClosure, ClosedTetSurfaceHasNoOpenOrPinchedEdge) {
  const SurfaceClosure s = checkSurfaceClosure(tetSurface(0, 1, 2, 3));
  EXPECT_EQ(s.open_edges, 0);
  EXPECT_EQ(s.pinched_edges, 0);
}

TEST(SurfaceClosure, MissingOrFlippedTriangleOpensItsEdges) {
  Eigen::Matrix3Xi t = tetSurface(0, 1, 2, 3);
  EXPECT_EQ(checkSurfaceClosure(t.leftCols(3)).open_edges, 3);
  std::swap(t(0, 0), t(1, 0));
  EXPECT_EQ(checkSurfaceClosure(t).open_edges, 3);
}

TEST(SurfaceClosure, TwoTetsSharingAnEdgeArePinchedThere) {
  Eigen::Matrix3Xi t(3, 8);
  t << tetSurface(0, 1, 2, 3), tetSurface(0, 1, 4, 5);
  const SurfaceClosure s = checkSurfaceClosure(t);
  EXPECT_EQ(s.open_edges, 0);
  EXPECT_EQ(s.pinched_edges, 1);
}

}  // namespace
}  // namespace surgical_sim::core
