#include "surgical_sim/core/cutting/surface_remap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>

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

// The criteria relaxed level by level over the IPs within `radius` of X, then over every IP,
// nearest first (ties to the lower index): the definition the grid search must reproduce.
RemapResult scanEveryIp(const EfgMappingSource& s, double radius, const V& X, const V& normal,
                        const std::vector<CutPlane>& planes, const std::vector<int>& ring) {
  const auto below = [&](const V& Y) {
    return std::all_of(planes.begin(), planes.end(),
                       [&](const CutPlane& p) { return (Y - p.point).dot(p.normal) < 0.0; });
  };
  const auto shares = [&](int ip, int r) {
    const std::vector<int>&a = s.ipParticles(ip), &b = s.ipParticles(r);
    return std::any_of(a.begin(), a.end(),
                       [&](int p) { return std::find(b.begin(), b.end(), p) != b.end(); });
  };
  std::vector<std::pair<double, int>> order;
  for (int i = 0; i < s.numIntegrationPoints(); ++i)
    order.emplace_back((s.ipRestPosition(i) - X).squaredNorm(), i);
  std::sort(order.begin(), order.end());
  for (const double limit : {radius * radius, std::numeric_limits<double>::infinity()})
    for (int level = 0; level <= 3; ++level)
      for (const auto& [d2, ip] : order) {
        if (d2 > limit) break;
        const V Y = s.ipRestPosition(ip);
        const bool tangent = level == 0 || level == 2, shared = level <= 1;
        if (!below(Y)) continue;
        if (tangent && normal.squaredNorm() > 0.0 && (Y - X).dot(normal) >= 0.0) continue;
        if (shared && !std::all_of(ring.begin(), ring.end(), [&](int r) { return shares(ip, r); }))
          continue;
        return {ip, static_cast<RemapRelaxation>(level)};
      }
  return {order.front().second, RemapRelaxation::kNearest};
}

TEST(SurfaceRemapper, GridSearchFindsWhatAScanOverEveryIpFinds) {
  // 12 x 9 x 7 IPs; vertices inside and outside the IPs' box, 0-3 random planes (slivers
  // included: two planes with opposite normals), random normals and 1-rings.
  const GridSource source(V(-0.1, 0.2, 0.0), Eigen::Vector3i(12, 9, 7), 0.05);
  const SurfaceRemapper remapper(source);
  // The first search's radius: one grid cell of about 4 IPs over the IPs' bounding box.
  const double radius = std::cbrt(4.0 * (0.05 * V(11, 8, 6)).prod() / (12 * 9 * 7));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto point = [&] {
    return V(0.2 + 0.5 * u(rng), 0.42 + 0.4 * u(rng), 0.17 + 0.3 * u(rng));
  };
  int relaxed = 0, nearest = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const V X = point();
    const V normal = trial % 5 == 0 ? V::Zero() : V(u(rng), u(rng), u(rng)).normalized();
    std::vector<CutPlane> planes;
    const int count = static_cast<int>(rng() % 4);
    for (int k = 0; k < count; ++k) {
      const V n = V(u(rng), u(rng), u(rng)).normalized();
      planes.push_back({point(), n});
      if (trial % 7 == 0) planes.push_back({planes.back().point + 0.04 * n, -n});
    }
    std::vector<int> ring;
    for (int k = static_cast<int>(rng() % 3); k > 0; --k)
      ring.push_back(
          static_cast<int>(rng() % static_cast<unsigned>(source.numIntegrationPoints())));
    const RemapResult want = scanEveryIp(source, radius, X, normal, planes, ring);
    const RemapResult got = remapper.find(X, normal, planes, ring);
    ASSERT_EQ(got.ip, want.ip) << "trial " << trial;
    ASSERT_EQ(got.relaxation, want.relaxation) << "trial " << trial;
    relaxed += want.relaxation != RemapRelaxation::kNone;
    nearest += want.relaxation == RemapRelaxation::kNearest;
  }
  EXPECT_GT(relaxed, 100);  // the search over every cell is exercised
  EXPECT_GT(nearest, 20);   // and the nearest-IP search
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
