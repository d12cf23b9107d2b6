#include "surgical_sim/core/cutting/surface_remap.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "efg_surface_test_util.h"

namespace surgical_sim::core {
namespace {

using efg_surface_test::GridSource;
using V = Eigen::Vector3d;

// IPs at the centres of a 4^3 grid of cells of side 0.25 in the unit box.
struct Grid {
  GridSource source{V::Zero(), Eigen::Vector3i(4, 4, 4), 0.25};
  SurfaceRemapper remapper{source};
  V ip(int i) const { return source.ipRestPosition(i); }
};

TEST(SurfaceRemapper, NearestIpWhenEveryCriterionHolds) {
  Grid g;
  const RemapResult r = g.remapper.find(V(0.3, 0.3, 1.0), V(0, 0, 1), {}, {});
  EXPECT_EQ(r.relaxation, RemapRelaxation::kNone);
  EXPECT_TRUE(g.ip(r.ip).isApprox(V(0.375, 0.375, 0.875)));
}

TEST(SurfaceRemapper, CutPlaneKeepsTheIpOnTheVertexSide) {
  Grid g;
  // Vertex at x = 0.45 whose side is x < 0.43 (plane normal +x): the nearer IP at x = 0.625 is
  // excluded.
  const std::vector<CutPlane> planes = {{V(0.43, 0, 0), V(1, 0, 0)}};
  const RemapResult r = g.remapper.find(V(0.55, 0.3, 1.0), V(0, 0, 1), planes, {});
  EXPECT_EQ(r.relaxation, RemapRelaxation::kNone);
  EXPECT_DOUBLE_EQ(g.ip(r.ip).x(), 0.375);
}

TEST(SurfaceRemapper, SharedParticlesWithTheOneRingRuleOutFarIps) {
  Grid g;
  // Ring IP in the cell at the origin: only IPs whose cell touches it share a particle.
  const int corner_ip = 0;
  const RemapResult r = g.remapper.find(V(0.6, 0.1, 0.1), V::Zero(), {}, {corner_ip});
  EXPECT_EQ(r.relaxation, RemapRelaxation::kNone);
  EXPECT_LT(g.ip(r.ip).x(), 0.5);  // the cell next to the corner, not the nearer x = 0.625 one
}

TEST(SurfaceRemapper, CriteriaAreRelaxedTangentFirstWhenNoIpIsValid) {
  Grid g;
  // Outward normal -z at the top: every IP is above the tangent plane z = 2.
  const RemapResult r = g.remapper.find(V(0.3, 0.3, 2.0), V(0, 0, -1), {}, {});
  EXPECT_EQ(r.relaxation, RemapRelaxation::kTangent);
  EXPECT_TRUE(g.ip(r.ip).isApprox(V(0.375, 0.375, 0.875)));
  // Contradictory planes: only the nearest IP remains.
  const std::vector<CutPlane> planes = {{V(0.5, 0, 0), V(1, 0, 0)}, {V(0.5, 0, 0), V(-1, 0, 0)}};
  EXPECT_EQ(g.remapper.find(V(0.3, 0.3, 2.0), V(0, 0, 1), planes, {}).relaxation,
            RemapRelaxation::kNearest);
}

class EmptySource : public GridSource {
 public:
  EmptySource() : GridSource(V::Zero(), Eigen::Vector3i(0, 0, 0), 1.0) {}
};

TEST(SurfaceRemapper, SourceWithoutIpsIsRejected) {
  EmptySource source;
  EXPECT_THROW(SurfaceRemapper{source}, std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
