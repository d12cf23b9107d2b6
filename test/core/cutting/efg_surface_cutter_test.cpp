#include "surgical_sim/core/cutting/efg_surface_cutter.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>

#include "efg_surface_test_util.h"
#include "surgical_sim/core/cutting/edge_sweep_ccd.h"
#include "surgical_sim/core/mesh/surface_closure.h"
#include "surgical_sim/core/mesh/surface_generators.h"
#include "surgical_sim/core/mesh/surface_inside.h"

namespace surgical_sim::core {
namespace {

using efg_surface_test::boxSurface;
using efg_surface_test::components;
using efg_surface_test::GridSource;
using efg_surface_test::verticalSweep;
using V = Eigen::Vector3d;

constexpr double kCutX = 0.43;  // cut plane x = 0.43 through the unit box (no vertex on it)
constexpr double kTilt = 0.03;  // blade height z0 + kTilt y
constexpr double kTop = 1.513;  // blade start height: no step ends on a grid line of the box

struct UnitBox {
  GridSource source{V::Zero(), Eigen::Vector3i(4, 4, 4), 0.25};
  TriMesh surface = boxSurface(V::Zero(), V::Ones(), Eigen::Vector3i(4, 4, 4));
  EfgSurfaceCutter cutter{surface, source, EfgSurfaceCutOptions{0.2, 1e-9}};

  /// Static tissue: current positions are the rest positions.
  EfgSurfaceCutStep step(const BladeSweep& sweep) {
    const Eigen::Matrix3Xd x = cutter.restVertices();
    return cutter.cut(sweep, x, x);
  }
  /// Blade along y (longer than the box) descending in x = kCutX from z0 to z1.
  EfgSurfaceCutStep descend(double z0, double z1) {
    return step(verticalSweep(kCutX, -0.5, 1.5, z0, z1, kTilt));
  }
  /// `steps` steps of dz from height z0.
  void descendSteps(double z0, double dz, int steps) {
    for (int i = 0; i < steps; ++i) descend(z0 - dz * i, z0 - dz * (i + 1));
  }
};

void expectClosed(const EfgSurfaceCutter& c) {
  const SurfaceClosure closure = checkSurfaceClosure(c.triangles());
  EXPECT_EQ(closure.open_edges, 0);
  EXPECT_EQ(closure.pinched_edges, 0);
}

/// Enclosed volume [m^3] of every connected component.
std::vector<double> pieceVolumes(const EfgSurfaceCutter& c, std::vector<int>& piece) {
  const Eigen::Matrix3Xi tris = c.triangles();
  int count = 0;
  piece = components(c.numVertices(), tris, count);
  std::vector<double> volume(static_cast<std::size_t>(count), 0.0);
  const Eigen::Matrix3Xd X = c.restVertices();
  for (Eigen::Index t = 0; t < tris.cols(); ++t)
    volume[static_cast<std::size_t>(piece[static_cast<std::size_t>(tris(0, t))])] +=
        X.col(tris(0, t)).dot(X.col(tris(1, t)).cross(X.col(tris(2, t)))) / 6.0;
  return volume;
}

/// Per vertex, the enclosed volume of its piece [m^3] (0 for a vertex in no triangle).
std::vector<double> vertexPieceVolumes(const EfgSurfaceCutter& c) {
  std::vector<int> piece;
  const std::vector<double> volume = pieceVolumes(c, piece);
  std::vector<double> out(piece.size(), 0.0);
  for (std::size_t v = 0; v < piece.size(); ++v)
    if (piece[v] >= 0) out[v] = volume[static_cast<std::size_t>(piece[v])];
  return out;
}

/// The unit box cut through at x = kCutX: two pieces of volumes kCutX and 1 - kCutX.
void expectCutInTwoAtCutX(const EfgSurfaceCutter& c) {
  std::vector<int> piece;
  std::vector<double> v = pieceVolumes(c, piece);
  ASSERT_EQ(v.size(), 2u);
  std::sort(v.begin(), v.end());
  EXPECT_NEAR(v[0], kCutX, 1e-9);
  EXPECT_NEAR(v[1], 1.0 - kCutX, 1e-9);
}

TEST(EfgSurfaceCutter, StraightCutThroughABoxLeavesTwoClosedPiecesOfTheRightVolumes) {
  UnitBox box;
  bool completed = false;
  for (int i = 0; i < 40; ++i) {
    const double z0 = kTop - 0.05 * i;
    const EfgSurfaceCutStep s = box.descend(z0, z0 - 0.05);
    completed = completed || s.completed;
    EXPECT_EQ(s.ignored_crossings, 0) << "step " << i;
    expectClosed(box.cutter);
  }
  EXPECT_TRUE(completed);
  EXPECT_FALSE(box.cutter.cutActive());
  std::vector<int> piece;
  const std::vector<double> volume = pieceVolumes(box.cutter, piece);
  ASSERT_EQ(volume.size(), 2u);
  // The pieces are x < 0.43 and x > 0.43 of the unit box, each outward-oriented.
  const double left = std::min(volume[0], volume[1]), right = std::max(volume[0], volume[1]);
  EXPECT_NEAR(left, kCutX, 1e-9);
  EXPECT_NEAR(right, 1.0 - kCutX, 1e-9);
  // The two new sheets lie in the cut plane, oppositely oriented: normal +x on the left piece.
  const Eigen::Matrix3Xi tris = box.cutter.triangles();
  const Eigen::Matrix3Xd X = box.cutter.restVertices();
  int sheet = 0;
  for (Eigen::Index t = 0; t < tris.cols(); ++t) {
    const V a = X.col(tris(0, t)), b = X.col(tris(1, t)), c = X.col(tris(2, t));
    if (std::abs(a.x() - kCutX) + std::abs(b.x() - kCutX) + std::abs(c.x() - kCutX) > 1e-12)
      continue;
    ++sheet;
    const V n = (b - a).cross(c - a);
    const bool on_left =
        volume[static_cast<std::size_t>(piece[static_cast<std::size_t>(tris(0, t))])] < 0.5;
    EXPECT_GT(on_left ? n.x() : -n.x(), 0.0) << "triangle " << t;
  }
  EXPECT_GT(sheet, 0);
}

TEST(EfgSurfaceCutter, PartialCutSplitsTipTrianglesInFourAndTheTipFollowsTheBlade) {
  UnitBox box;
  box.descendSteps(kTop, 0.05, 10);      // down to 1.013
  box.descendSteps(kTop - 0.5, 0.1, 3);  // down to 0.713
  const double z = kTop - 0.8;
  ASSERT_TRUE(box.cutter.cutActive());
  expectClosed(box.cutter);
  // The two tips lie on the faces y = 0 and y = 1, where the blade pierces them.
  const Eigen::Matrix3Xd X = box.cutter.restVertices();
  std::vector<int> tips;
  for (int v : box.cutter.transientVertices())
    if (std::abs(X(1, v)) < 1e-12 || std::abs(X(1, v) - 1.0) < 1e-12) tips.push_back(v);
  ASSERT_EQ(tips.size(), 2u);
  for (int tip : tips) {
    EXPECT_NEAR(X(0, tip), kCutX, 1e-12);
    EXPECT_NEAR(X(2, tip), z + kTilt * X(1, tip), 1e-9);  // blade height at that y
    // Four face triangles (normal along y) hold the tip (the 4-split); the others are sheets.
    const Eigen::Matrix3Xi tris = box.cutter.triangles();
    int on_face = 0;
    for (Eigen::Index t = 0; t < tris.cols(); ++t) {
      if (tris(0, t) != tip && tris(1, t) != tip && tris(2, t) != tip) continue;
      const V n =
          (X.col(tris(1, t)) - X.col(tris(0, t))).cross(X.col(tris(2, t)) - X.col(tris(0, t)));
      on_face += std::abs(n.y()) > 0.999 * n.norm() ? 1 : 0;
    }
    EXPECT_EQ(on_face, 4);
  }
  // A small blade motion inside the same triangles moves the tips with it.
  box.descend(z, z - 0.01);
  const Eigen::Matrix3Xd Y = box.cutter.restVertices();
  for (int tip : tips) {
    EXPECT_NEAR(Y(0, tip), kCutX, 1e-12);
    EXPECT_NEAR(Y(2, tip), z - 0.01 + kTilt * Y(1, tip), 1e-9);
  }
}

TEST(EfgSurfaceCutter, EdgesShorterThanTheMinimumAreNotSplitAgain) {
  // w = 0.2 m, input edges 0.25 m and longer: the shortest split edge is 0.1 w.
  UnitBox box;
  ASSERT_DOUBLE_EQ(box.cutter.minSplitEdge(), 0.02);
  // Blades through the whole box ever closer to the grid line x = 0.25, each halfway between it
  // and the last: each would split the edges the last one left between them, ever shorter.
  int ignored = 0;
  for (int k = 0; k < 8; ++k) {
    const double x_cut = 0.25 + 0.01 / (1 << k);
    for (int i = 0; i < 20; ++i) {
      const double z0 = kTop - 0.1 * i;
      ignored += box.step(verticalSweep(x_cut, -0.5, 1.5, z0, z0 - 0.1, kTilt)).ignored_crossings;
    }
    expectClosed(box.cutter);
  }
  EXPECT_GT(ignored, 0);
  // The refinement stops near the shortest split edge. Splitting every edge instead leaves
  // 5,164 triangles and an edge of 3.9e-5 m here (978 and 1.5e-4 m with the minimum).
  EXPECT_LE(box.cutter.numTriangles(), 2000);
  const Eigen::Matrix3Xi tris = box.cutter.triangles();
  const Eigen::Matrix3Xd X = box.cutter.restVertices();
  double shortest = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < tris.cols(); ++t)
    for (int k = 0; k < 3; ++k)
      shortest = std::min(shortest, (X.col(tris(k, t)) - X.col(tris((k + 1) % 3, t))).norm());
  EXPECT_GE(shortest, 0.005 * box.cutter.minSplitEdge());
}

TEST(EfgSurfaceCutter, SlowBladeMotionAddsNoTriangles) {
  UnitBox box;
  box.descendSteps(kTop, 0.05, 12);  // z ~ 0.913
  ASSERT_TRUE(box.cutter.cutActive());
  const Eigen::Index before = box.cutter.triangles().cols();
  for (int i = 0; i < 10; ++i) {
    const double z = kTop - 0.6 - 1e-4 * i;
    const EfgSurfaceCutStep s = box.descend(z, z - 1e-4);
    EXPECT_EQ(s.crossed_edges, 0);
    EXPECT_EQ(box.cutter.triangles().cols(), before) << "step " << i;
  }
}

TEST(EfgSurfaceCutter, EveryVertexMapsToAnIpOnItsOwnSideAndPairsSplitAcrossTheCut) {
  UnitBox box;
  box.descendSteps(kTop, 0.05, 40);
  ASSERT_FALSE(box.cutter.cutActive());
  std::vector<int> piece;
  const std::vector<double> volume = pieceVolumes(box.cutter, piece);
  const Eigen::Matrix3Xd X = box.cutter.restVertices();
  int pairs = 0;
  for (int v = 0; v < box.cutter.numVertices(); ++v) {
    if (!box.cutter.vertexUsed(v)) continue;
    const bool left = volume[static_cast<std::size_t>(piece[static_cast<std::size_t>(v)])] < 0.5;
    const double ip_x = box.source.ipRestPosition(box.cutter.vertexIp(v)).x();
    EXPECT_EQ(ip_x < kCutX, left) << "vertex " << v;
    const int t = box.cutter.twin(v);
    if (t < 0) continue;
    ++pairs;
    EXPECT_EQ(X.col(v), X.col(t));  // same rest point, bit for bit
    EXPECT_NE(piece[static_cast<std::size_t>(v)], piece[static_cast<std::size_t>(t)]);
  }
  EXPECT_GT(pairs, 0);
  // Mapping rows are partitions of unity (trilinear weights).
  std::vector<int> p;
  std::vector<double> w;
  for (int v = 0; v < box.cutter.numVertices(); ++v)
    if (box.cutter.vertexUsed(v)) {
      box.cutter.mappingRow(v, p, w);
      double sum = 0.0;
      for (double x : w) sum += x;
      EXPECT_NEAR(sum, 1.0, 1e-12);
    }
  // The mapping holds each used vertex's row, by ascending particle, and nothing else.
  const SurfaceMapping m = box.cutter.mapping(box.source.numParticles());
  EXPECT_EQ(m.numSlots(), box.cutter.numVertices());
  std::vector<int> used;
  for (int v = 0; v < box.cutter.numVertices(); ++v) {
    const SurfaceMapping::Row row = m.row(v);
    if (!box.cutter.vertexUsed(v)) {
      EXPECT_EQ(row.size, 0) << v;
      continue;
    }
    used.push_back(v);
    box.cutter.mappingRow(v, p, w);
    std::vector<std::pair<int, double>> expected;
    for (std::size_t k = 0; k < p.size(); ++k) expected.emplace_back(p[k], w[k]);
    std::sort(expected.begin(), expected.end());
    ASSERT_EQ(row.size, static_cast<int>(expected.size())) << v;
    for (int k = 0; k < row.size; ++k) {
      EXPECT_EQ(row.nodes[k], expected[static_cast<std::size_t>(k)].first);
      EXPECT_EQ(row.weights[k], expected[static_cast<std::size_t>(k)].second);
    }
  }
  EXPECT_EQ(m.vertices(), used);
  EXPECT_THROW(box.cutter.mapping(1), std::invalid_argument);
}

TEST(EfgSurfaceCutter, CrossingsFollowThePiecesWhereTheyAreNotWhereTheyRest) {
  // Two boxes cut in two at x = kCutX. In one, the larger piece is moved 50 m along x: a blade
  // through where it rests cuts nothing, and a blade through it crosses the same edges as the
  // same blade 50 m back crosses in the box left in place.
  UnitBox moved, still;
  moved.descendSteps(kTop, 0.05, 40);
  still.descendSteps(kTop, 0.05, 40);
  ASSERT_FALSE(moved.cutter.cutActive());
  std::vector<int> piece;
  const std::vector<double> volume = pieceVolumes(moved.cutter, piece);
  Eigen::Matrix3Xd x = moved.cutter.restVertices();
  for (int v = 0; v < moved.cutter.numVertices(); ++v)
    if (moved.cutter.vertexUsed(v) &&
        volume[static_cast<std::size_t>(piece[static_cast<std::size_t>(v)])] > 0.5)
      x(0, v) += 50.0;
  EXPECT_EQ(moved.cutter.cut(verticalSweep(0.7, -0.5, 1.5, 1.5, 1.4, kTilt), x, x).crossed_edges,
            0);
  const EfgSurfaceCutStep there =
      moved.cutter.cut(verticalSweep(50.7, -0.5, 1.5, 1.5, -0.5, kTilt), x, x);
  const EfgSurfaceCutStep here = still.step(verticalSweep(0.7, -0.5, 1.5, 1.5, -0.5, kTilt));
  EXPECT_GT(here.crossed_edges, 0);
  EXPECT_EQ(there.crossed_edges, here.crossed_edges);
  EXPECT_EQ(there.completed, here.completed);
  expectClosed(moved.cutter);
}

/// What a sweep test of the blade against every candidate of `c` (no running cut) finds: the
/// crossed edges of its triangles, and the vertices whose segment to their IP it crosses among
/// those the class comment lists (mapped, in a triangle, motion grown by 3 times the rest
/// distance to the IP meeting the swept box), ascending.
struct Crossings {
  int edges = 0;
  std::vector<int> segments;
};

Crossings everyCrossing(const EfgSurfaceCutter& c, const EfgMappingSource& source,
                        const BladeSweep& s, const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1,
                        double tol) {
  const auto crosses = [&](const V& a0, const V& b0, const V& a1, const V& b1) {
    for (Eigen::Index i = 0; i + 1 < s.start.cols(); ++i)
      if (edgeSweepCrossing(s.start.col(i), s.start.col(i + 1), s.end.col(i), s.end.col(i + 1), a0,
                            b0, a1, b1, tol))
        return true;
    return false;
  };
  const Eigen::Matrix3Xi tris = c.triangles();
  std::set<std::pair<int, int>> edges;
  std::vector<char> in_triangle(static_cast<std::size_t>(c.numVertices()), 0);
  for (Eigen::Index t = 0; t < tris.cols(); ++t)
    for (int k = 0; k < 3; ++k) {
      edges.insert(std::minmax(tris(k, t), tris((k + 1) % 3, t)));
      in_triangle[static_cast<std::size_t>(tris(k, t))] = 1;
    }
  Crossings out;
  for (const auto& [a, b] : edges)
    out.edges += crosses(x0.col(a), x0.col(b), x1.col(a), x1.col(b)) ? 1 : 0;
  const Eigen::Matrix3Xd X = c.restVertices();
  for (int v = 0; v < c.numVertices(); ++v) {
    const int ip = c.vertexIp(v);
    if (!in_triangle[static_cast<std::size_t>(v)] || ip < 0) continue;
    const V x_ip = source.ipPosition(ip);
    if (source.ipRestPosition(ip) != V(X.col(v)) && crosses(x0.col(v), x_ip, x1.col(v), x_ip))
      out.segments.push_back(v);
  }
  return out;
}

TEST(EfgSurfaceCutter, FindsEveryEdgeCrossingOfAPieceMovedFarDeformedAndSweptFar) {
  // The box cut in two; its larger piece moved 50 m along x, every vertex displaced at random by
  // up to 0.15 m along each axis (other displacements at the step end, where both pieces have
  // risen 2 m); the blade descends 6 m through the moved piece in one step. The cutter finds
  // (crosses or ignores) every edge that a sweep test of the whole surface finds crossed.
  UnitBox box;
  box.descendSteps(kTop, 0.05, 40);
  const std::vector<double> volume = vertexPieceVolumes(box.cutter);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  Eigen::Matrix3Xd x0 = box.cutter.restVertices(), x1 = x0;
  for (int v = 0; v < box.cutter.numVertices(); ++v) {
    const V shift(volume[static_cast<std::size_t>(v)] > 0.5 ? 50.0 : 0.0, 0.0, 0.0);
    x0.col(v) += shift + V(u(rng), u(rng), u(rng));
    x1.col(v) += shift + V(0.0, 0.0, 2.0) + V(u(rng), u(rng), u(rng));
  }
  const BladeSweep s = verticalSweep(50.7, -0.5, 1.5, 4.0, -2.0, kTilt);
  const Crossings expected = everyCrossing(box.cutter, box.source, s, x0, x1, 1e-9);
  const EfgSurfaceCutStep r = box.cutter.cut(s, x0, x1);
  EXPECT_GT(expected.edges, 10);
  EXPECT_EQ(r.crossed_edges + r.ignored_crossings, expected.edges);
  expectClosed(box.cutter);
}

TEST(EfgSurfaceCutter, FindsEveryVertexToIpSegmentCrossingUnderLargeMotion) {
  // Every vertex displaced at random by up to 0.08 m along x and y and 0.04 m along z (other
  // displacements at the step end) while the box moves 0.3 m along x over the step (its IPs
  // stay); a blade inside it, under its top face, sweeps across between two columns of IPs and
  // crosses no edge. The remapped vertices are exactly those whose segment to their IP a sweep
  // test of every candidate finds crossed (some only late in the step, the vertex's start and its
  // IP on the same side of the blade).
  UnitBox box;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto noise = [&] { return V(0.08 * u(rng), 0.08 * u(rng), 0.04 * u(rng)); };
  Eigen::Matrix3Xd x0 = box.cutter.restVertices(), x1 = x0;
  for (int v = 0; v < box.cutter.numVertices(); ++v) {
    x0.col(v) += V(-0.3, 0.0, 0.0) + noise();
    x1.col(v) += noise();
  }
  BladeSweep s;
  s.start.resize(3, 2);
  s.end.resize(3, 2);
  s.start << 0.6, 0.6, 0.2, 0.8, 0.95, 0.95;
  s.end << 0.4, 0.4, 0.2, 0.8, 0.95, 0.95;
  const Crossings expected = everyCrossing(box.cutter, box.source, s, x0, x1, 1e-9);
  ASSERT_EQ(expected.edges, 0);
  const EfgSurfaceCutStep r = box.cutter.cut(s, x0, x1);
  EXPECT_EQ(r.crossed_edges + r.ignored_crossings, 0);
  EXPECT_GT(expected.segments.size(), 2u);
  EXPECT_EQ(r.remapped, expected.segments);
}

TEST(EfgSurfaceCutter, BladeThatMissesChangesNothingBitForBit) {
  UnitBox box;
  const Eigen::Matrix3Xd X0 = box.cutter.restVertices();
  const Eigen::Matrix3Xi T0 = box.cutter.triangles();
  std::vector<std::vector<double>> rows;
  std::vector<int> p;
  std::vector<double> w;
  for (int v = 0; v < box.cutter.numVertices(); ++v) {
    box.cutter.mappingRow(v, p, w);
    rows.push_back(w);
  }
  // Passes beside the box (x = 1.3) and above it.
  EfgSurfaceCutStep s = box.step(verticalSweep(1.3, -0.5, 1.5, 1.5, -0.5, kTilt));
  s = box.step(verticalSweep(kCutX, -0.5, 1.5, 3.0, 1.2, kTilt));
  EXPECT_EQ(s.crossed_edges, 0);
  EXPECT_TRUE(s.remapped.empty());
  EXPECT_EQ(box.cutter.restVertices(), X0);
  EXPECT_EQ(box.cutter.triangles(), T0);
  for (int v = 0; v < box.cutter.numVertices(); ++v) {
    box.cutter.mappingRow(v, p, w);
    EXPECT_EQ(w, rows[static_cast<std::size_t>(v)]);
  }
}

TEST(EfgSurfaceCutter, OneBigStepGivesTheSameTopologyClassAsManySmallSteps) {
  UnitBox big, small;
  const EfgSurfaceCutStep s = big.descend(kTop, -0.5);
  EXPECT_TRUE(s.completed);
  small.descendSteps(kTop, 0.01, 200);
  for (UnitBox* b : {&big, &small}) {
    expectClosed(b->cutter);
    EXPECT_FALSE(b->cutter.cutActive());
    expectCutInTwoAtCutX(b->cutter);
  }
}

TEST(EfgSurfaceCutter, StaticBladeCutsTissueMovingThroughIt) {
  // The box rises through a static blade (current = rest + lift): same pieces as a falling blade.
  UnitBox box;
  const BladeSweep still = verticalSweep(kCutX, -0.5, 1.5, 0.513, 0.513, kTilt);
  for (int i = 0; i < 40; ++i) {
    const Eigen::Matrix3Xd X = box.cutter.restVertices();
    const Eigen::Matrix3Xd x0 = X.colwise() + V(0, 0, -1.0 + 0.05 * i);
    const Eigen::Matrix3Xd x1 = X.colwise() + V(0, 0, -0.95 + 0.05 * i);
    box.cutter.cut(still, x0, x1);
    expectClosed(box.cutter);
  }
  EXPECT_FALSE(box.cutter.cutActive());
  expectCutInTwoAtCutX(box.cutter);
}

TEST(EfgSurfaceCutter, BladeCrossingAVertexToIpSegmentAddsAPlaneAndRemaps) {
  UnitBox box;
  // A short blade inside the box near the top face, crossing vertex-IP segments only.
  const Eigen::Matrix3Xd X = box.cutter.restVertices();
  int v = -1;
  for (int i = 0; i < X.cols(); ++i)
    if ((X.col(i) - V(0.5, 0.5, 1.0)).norm() < 1e-12) v = i;
  ASSERT_GE(v, 0);
  const V ip = box.source.ipRestPosition(box.cutter.vertexIp(v));
  const V mid = 0.5 * (X.col(v) + ip);
  BladeSweep s;
  s.start.resize(3, 2);
  s.end.resize(3, 2);
  s.start << mid.x() - 0.05, mid.x() - 0.05, mid.y() - 0.02, mid.y() + 0.02, mid.z(), mid.z();
  s.end << mid.x() + 0.05, mid.x() + 0.05, mid.y() - 0.02, mid.y() + 0.02, mid.z(), mid.z();
  const EfgSurfaceCutStep r = box.step(s);
  EXPECT_EQ(r.crossed_edges, 0);
  ASSERT_EQ(box.cutter.vertexPlanes(v).size(), 1u);
  EXPECT_NE(std::find(r.remapped.begin(), r.remapped.end(), v), r.remapped.end());
  // The new IP is below the plane (on the vertex's side of the blade).
  const CutPlane& plane = box.cutter.vertexPlanes(v)[0];
  EXPECT_LT((box.source.ipRestPosition(box.cutter.vertexIp(v)) - plane.point).dot(plane.normal),
            0.0);
  expectClosed(box.cutter);
}

TEST(EfgSurfaceCutter, VolumeCutRemapsTheVerticesOfChangedIps) {
  UnitBox box;
  const int ip = box.cutter.vertexIp(0);
  std::vector<int> mapped;
  for (int v = 0; v < box.cutter.numVertices(); ++v)
    if (box.cutter.vertexIp(v) == ip) mapped.push_back(v);
  // A volume cut separates the IP from its neighbours: it keeps only particles of a far cell.
  box.source.setParticles(ip, box.source.ipParticles(box.source.numIntegrationPoints() - 1));
  const std::vector<int> remapped = box.cutter.remapVerticesOfIps({ip});
  EXPECT_EQ(remapped, mapped);
  // A vertex with a neighbour on an unchanged IP leaves the separated IP; every row is the
  // source's weights of its IP at the vertex.
  const Eigen::Matrix3Xd X = box.cutter.restVertices();
  const Eigen::Matrix3Xi tris = box.cutter.triangles();
  std::vector<int> p, q;
  std::vector<double> w, u;
  for (int v : remapped) {
    bool outside_neighbour = false;
    for (Eigen::Index t = 0; t < tris.cols(); ++t)
      for (int k = 0; k < 3; ++k)
        if (tris(k, t) == v)
          for (int j = 0; j < 3; ++j)
            outside_neighbour = outside_neighbour ||
                                std::find(mapped.begin(), mapped.end(), tris(j, t)) == mapped.end();
    if (outside_neighbour) {
      EXPECT_NE(box.cutter.vertexIp(v), ip) << "vertex " << v;
    }
    box.cutter.mappingRow(v, p, w);
    box.source.pointWeights(box.cutter.vertexIp(v), X.col(v), q, u);
    EXPECT_EQ(p, q);
    EXPECT_EQ(w, u);
  }
  EXPECT_THROW(box.cutter.remapVerticesOfIps({-1}), std::invalid_argument);
}

/// A blade of length 4 through a random point within `spread` of the origin along each axis,
/// moving 4 m across itself in 4 steps: the steps' sweeps.
std::array<BladeSweep, 4> randomCrossingSweeps(std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto unit = [&] { return V(u(rng), u(rng), u(rng)).normalized(); };
  const V centre = spread * V(u(rng), u(rng), u(rng)), along = unit();
  V motion = unit();
  motion = (motion - motion.dot(along) * along).normalized();
  const V a = centre - 2.0 * along - 2.0 * motion, b = centre + 2.0 * along - 2.0 * motion;
  std::array<BladeSweep, 4> steps;
  for (int k = 0; k < 4; ++k) {
    BladeSweep& s = steps[static_cast<std::size_t>(k)];
    s.start.resize(3, 2);
    s.end.resize(3, 2);
    s.start << a + k * motion, b + k * motion;
    s.end << a + (k + 1) * motion, b + (k + 1) * motion;
  }
  return steps;
}

TEST(EfgSurfaceCutter, RandomSweepsNeverLeaveOpenOrPinchedEdgesOrNonFiniteValues) {
  // 300 seeded random sweeps, 25 on each of 12 fresh spheres (so the surface stays small).
  const TriMesh sphere = makeIcosphere(2);
  GridSource source(V::Constant(-1.0), Eigen::Vector3i(5, 5, 5), 0.4);
  std::mt19937 rng(19);
  int cuts = 0;
  std::vector<int> p;
  std::vector<double> w;
  for (int body = 0; body < 12; ++body) {
    EfgSurfaceCutter cutter(sphere, source, EfgSurfaceCutOptions{0.3, 1e-9});
    for (int sweep = 0; sweep < 25; ++sweep) {
      const std::array<BladeSweep, 4> steps = randomCrossingSweeps(rng, 0.8);
      for (int k = 0; k < 4; ++k) {
        const Eigen::Matrix3Xd x = cutter.restVertices();
        const EfgSurfaceCutStep r = cutter.cut(steps[static_cast<std::size_t>(k)], x, x);
        cuts += r.completed || r.crack ? 1 : 0;
        const SurfaceClosure closure = checkSurfaceClosure(cutter.triangles());
        ASSERT_EQ(closure.open_edges, 0) << "body " << body << " sweep " << sweep << " step " << k;
        ASSERT_EQ(closure.pinched_edges, 0) << "body " << body << " sweep " << sweep;
      }
      ASSERT_TRUE(cutter.restVertices().allFinite());
    }
    for (int v = 0; v < cutter.numVertices(); ++v) {
      if (!cutter.vertexUsed(v)) continue;
      cutter.mappingRow(v, p, w);
      for (double x : w) ASSERT_TRUE(std::isfinite(x));
    }
  }
  EXPECT_GT(cuts, 150);
  std::cout << "[ info ] 300 random sweeps: " << cuts << " cuts closed or left as cracks\n";
}

/// The largest number of triangles at one vertex.
int largestFan(const EfgSurfaceCutter& c) {
  const Eigen::Matrix3Xi tris = c.triangles();
  std::vector<int> count(static_cast<std::size_t>(c.numVertices()), 0);
  for (Eigen::Index t = 0; t < tris.cols(); ++t)
    for (int k = 0; k < 3; ++k) ++count[static_cast<std::size_t>(tris(k, t))];
  return *std::max_element(count.begin(), count.end());
}

/// The unit box with a fine top face (64 x 64 squares, 8 x 8 on the other faces' long sides).
struct FineTopBox {
  GridSource source{V::Zero(), Eigen::Vector3i(4, 4, 4), 0.25};
  TriMesh surface = boxSurface(V::Zero(), V::Ones(), Eigen::Vector3i(64, 64, 8));
  EfgSurfaceCutter cutter{surface, source, EfgSurfaceCutOptions{0.2, 1e-9}};
};

TEST(EfgSurfaceCutter, CrackWithALongChainOfCrossingsLeavesNoFan) {
  // A 0.8 m blade enters the fine top face and ends under it within one step: a crack whose
  // chain crosses ~100 edges while its front between the tips has 4 segments (w = 0.2 m).
  // Meshed directly, each of the front's 5 vertices would take ~20 chain vertices.
  FineTopBox box;
  const Eigen::Matrix3Xd x = box.cutter.restVertices();
  const EfgSurfaceCutStep r =
      box.cutter.cut(verticalSweep(kCutX, 0.1, 0.9, 1.05, 0.9, kTilt), x, x);
  EXPECT_TRUE(r.crack);
  EXPECT_GT(r.crossed_edges, 90);
  expectClosed(box.cutter);
  std::cout << "[ info ] crack of " << r.crossed_edges << " crossings: largest fan "
            << largestFan(box.cutter) << " triangles\n";
  EXPECT_LE(largestFan(box.cutter), 10);
  // Every new vertex is mapped.
  for (int v = 0; v < box.cutter.numVertices(); ++v) {
    if (box.cutter.vertexUsed(v)) {
      EXPECT_GE(box.cutter.vertexIp(v), 0) << v;
    }
  }
}

TEST(EfgSurfaceCutter, OverlappingCracksKeepTheSurfaceBounded) {
  // 60 cracks 0.3 m long in the middle half of the fine top face (centres and directions from
  // golden sequences): later blades cross earlier cracks' sheets. The surface stays closed and
  // no vertex gathers a fan. Fans there would feed on themselves: a blade crossing a fan near
  // its apex crosses all its triangles, and its chain of crossings then faces a short front
  // (ungraded, the 60 cuts left 350k triangles, 29,559 of them at one vertex).
  FineTopBox box;
  const int initial = box.cutter.numTriangles();
  int crossed = 0;
  for (int c = 0; c < 60; ++c) {
    const double angle = c * 2.399963229728653;  // golden angle [rad]
    const V along(std::cos(angle), std::sin(angle), 0.0);
    const V mid(0.25 + 0.5 * std::fmod(0.5 + c * 0.7548776662466927, 1.0),
                0.25 + 0.5 * std::fmod(0.5 + c * 0.5698402909980532, 1.0), 0.0);
    BladeSweep s;
    s.start.resize(3, 2);
    s.end.resize(3, 2);
    for (int k = 0; k < 2; ++k) {
      const V p = mid + (k ? 0.15 : -0.15) * along;
      s.start.col(k) = V(p.x(), p.y(), 1.05);
      s.end.col(k) = V(p.x(), p.y(), 0.9);
    }
    const Eigen::Matrix3Xd x = box.cutter.restVertices();
    crossed += box.cutter.cut(s, x, x).crossed_edges;
    const SurfaceClosure closure = checkSurfaceClosure(box.cutter.triangles());
    ASSERT_EQ(closure.open_edges, 0) << "cut " << c;
    ASSERT_EQ(closure.pinched_edges, 0) << "cut " << c;
  }
  std::cout << "[ info ] 60 overlapping cracks: " << crossed << " crossings, triangles " << initial
            << " -> " << box.cutter.numTriangles() << ", largest fan " << largestFan(box.cutter)
            << "\n";
  EXPECT_LE(largestFan(box.cutter), 32);
  EXPECT_LE(box.cutter.numTriangles(), 150000);
}

TEST(EfgSurfaceCutter, DegenerateHugeAndTinySweepsKeepTheSurfaceClosedAndMapped) {
  // 160 hostile sweeps on the 16 x 16 box, four kinds in turn: a blade exactly on a grid plane
  // (through vertices, along edges); a 2 km blade falling 10 m and twisting in one step; a
  // 1 nm sweep at the top face's height; a short crack at random. After every sweep the surface
  // is closed and edge-manifold and every used vertex has an IP and a finite mapping row whose
  // weights sum to 1.
  const GridSource source(V::Zero(), Eigen::Vector3i(4, 4, 4), 0.25);
  EfgSurfaceCutter cutter(boxSurface(V::Zero(), V::Ones(), Eigen::Vector3i(16, 16, 16)), source,
                          EfgSurfaceCutOptions{0.2, 1e-9});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<int> p;
  std::vector<double> w;
  int cuts = 0;
  for (int i = 0; i < 160; ++i) {
    BladeSweep s;
    s.start.resize(3, 2);
    s.end.resize(3, 2);
    const double gx = std::round(16.0 * u(rng)) / 16.0, gy = std::round(16.0 * u(rng)) / 16.0;
    switch (i % 4) {
      case 0:
        s.start << gx, gx, -0.5, 1.5, 1.2, 1.2;
        s.end << gx, gx, -0.5, 1.5, 0.5 * u(rng), 0.5 * u(rng);
        break;
      case 1:
        s.start << -1e3, 1e3, gy, gy, 5.0, 5.0;
        s.end << -1e3, 1e3, gy + 0.3, gy - 0.3, -5.0, -5.0;
        break;
      case 2:
        s.start << gx, gx + 0.1, gy, gy, 1.0, 1.0;
        s.end = s.start;
        s.end.row(2).array() -= 1e-9;
        break;
      default: {
        const double angle = 2.0 * M_PI * u(rng);
        const V mid(0.2 + 0.6 * u(rng), 0.2 + 0.6 * u(rng), 0.0);
        for (int k = 0; k < 2; ++k) {
          const V q = mid + (k ? 0.15 : -0.15) * V(std::cos(angle), std::sin(angle), 0.0);
          s.start.col(k) = V(q.x(), q.y(), 1.05);
          s.end.col(k) = V(q.x(), q.y(), 0.9);
        }
      }
    }
    const Eigen::Matrix3Xd x = cutter.restVertices();
    const EfgSurfaceCutStep r = cutter.cut(s, x, x);
    cuts += r.completed || r.crack ? 1 : 0;
    const SurfaceClosure closure = checkSurfaceClosure(cutter.triangles());
    ASSERT_EQ(closure.open_edges, 0) << "sweep " << i;
    ASSERT_EQ(closure.pinched_edges, 0) << "sweep " << i;
    ASSERT_TRUE(cutter.restVertices().allFinite()) << "sweep " << i;
    for (int v = 0; v < cutter.numVertices(); ++v) {
      if (!cutter.vertexUsed(v)) continue;
      ASSERT_GE(cutter.vertexIp(v), 0) << "sweep " << i << " vertex " << v;
      cutter.mappingRow(v, p, w);
      double sum = 0.0;
      for (double x_w : w) sum += x_w;
      ASSERT_NEAR(sum, 1.0, 1e-6) << "sweep " << i << " vertex " << v;
    }
  }
  EXPECT_GT(cuts, 80);
}

/// Positions [m] of the cutter's vertices (its mapping rows) for particle positions x; free
/// slots at 0.
Eigen::Matrix3Xd mappedVertices(const EfgSurfaceCutter& cutter, const Eigen::VectorXd& x) {
  Eigen::Matrix3Xd out = Eigen::Matrix3Xd::Zero(3, cutter.numVertices());
  std::vector<int> p;
  std::vector<double> w;
  for (int v = 0; v < cutter.numVertices(); ++v) {
    if (!cutter.vertexUsed(v)) continue;
    cutter.mappingRow(v, p, w);
    for (std::size_t a = 0; a < p.size(); ++a) out.col(v) += w[a] * x.segment<3>(3 * p[a]);
  }
  return out;
}

/// What two cutters on `sphere` found in the same random crossing sweeps (`bodies` bodies of
/// `sweeps` sweeps of 4 steps each) while the body moves far (a rotation of up to 0.6 rad and a
/// translation of up to 3 m, its diameter is 2 m, different at the step start and end, the
/// sweep carried along) and deforms (each particle moved by up to 0.12 m along each axis). One
/// classifies every vertex, the other only those of the clusters its particle-motion bounds
/// keep: every step must give the same result. The IPs follow the particles (at the step end).
struct MotionBoundsRun {
  int cuts = 0, crossed = 0, remapped = 0;
};
MotionBoundsRun compareMotionBounds(const TriMesh& sphere, int bodies, int sweeps) {
  GridSource source(V::Constant(-1.0), Eigen::Vector3i(5, 5, 5), 0.4);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd rest(3 * source.numParticles());
  for (int p = 0; p < source.numParticles(); ++p)
    rest.segment<3>(3 * p) = source.particleRestPosition(p);
  MotionBoundsRun run;
  const std::vector<int> unchanged;
  Eigen::VectorXd x1 = rest;
  source.current = &x1;
  for (int body = 0; body < bodies; ++body) {
    x1 = rest;
    EfgSurfaceCutter every(sphere, source, EfgSurfaceCutOptions{0.3, 1e-9});
    EfgSurfaceCutter bounded(sphere, source, EfgSurfaceCutOptions{0.3, 1e-9});
    for (int sweep = 0; sweep < sweeps; ++sweep) {
      const std::array<BladeSweep, 4> steps = randomCrossingSweeps(rng, 0.8);
      for (int k = 0; k < 4; ++k) {
        const auto rigid = [&] {
          Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
          t.rotate(Eigen::AngleAxisd(0.6 * u(rng), V(u(rng), u(rng), u(rng)).normalized()));
          t.pretranslate(3.0 * V(u(rng), u(rng), u(rng)));
          return t;
        };
        const Eigen::Isometry3d t0 = rigid(), t1 = rigid();
        Eigen::VectorXd x0 = rest;
        for (int p = 0; p < source.numParticles(); ++p) {
          x0.segment<3>(3 * p) = t0 * V(rest.segment<3>(3 * p)) + 0.12 * V(u(rng), u(rng), u(rng));
          x1.segment<3>(3 * p) = t1 * V(rest.segment<3>(3 * p)) + 0.12 * V(u(rng), u(rng), u(rng));
        }
        BladeSweep s = steps[static_cast<std::size_t>(k)];
        s.start = t0 * s.start;
        s.end = t1 * s.end;
        const Eigen::Matrix3Xd v0 = mappedVertices(every, x0), v1 = mappedVertices(every, x1);
        const EfgSurfaceCutStep a = every.cut(s, v0, v1);
        const EfgParticleMotion motion{x0, x1, unchanged};
        const EfgSurfaceCutStep b = bounded.cut(s, v0, v1, &motion);
        const std::string at = "body " + std::to_string(body) + " sweep " + std::to_string(sweep) +
                               " step " + std::to_string(k);
        EXPECT_EQ(a.crossed_edges, b.crossed_edges) << at;
        EXPECT_EQ(a.ignored_crossings, b.ignored_crossings) << at;
        EXPECT_EQ(a.completed, b.completed) << at;
        EXPECT_EQ(a.crack, b.crack) << at;
        EXPECT_EQ(a.remapped, b.remapped) << at;
        EXPECT_EQ(every.triangles(), bounded.triangles()) << at;
        if (::testing::Test::HasFailure()) return run;
        run.cuts += a.completed || a.crack ? 1 : 0;
        run.crossed += a.crossed_edges;
        run.remapped += static_cast<int>(a.remapped.size());
      }
    }
  }
  return run;
}

TEST(EfgSurfaceCutter, ParticleMotionBoundsFindWhatThePassOverEveryVertexFinds) {
  const MotionBoundsRun run = compareMotionBounds(makeIcosphere(2), 4, 10);
  EXPECT_GT(run.cuts, 20);
  EXPECT_GT(run.crossed, 500);
  std::cout << "[ info ] 160 moving sweeps: " << run.cuts << " cuts, " << run.crossed
            << " crossed edges, " << run.remapped
            << " remapped vertices, the same with and without the motion bounds\n";
}

TEST(EfgSurfaceCutter, ParticleMotionBoundsSkipWholeSuperGroupsOfAFineSurface) {
  // 81,920 triangles: 122,880 edges in 3,840 clusters, 120 groups and 4 super-groups, so the
  // bounded pass skips super-groups and groups as well as clusters.
  const MotionBoundsRun run = compareMotionBounds(makeIcosphere(6), 1, 6);
  EXPECT_GT(run.cuts, 2);
  EXPECT_GT(run.crossed, 500);
}

TEST(EfgSurfaceCutter, ParticleMotionBoundsKeepTheVertexToIpSegmentsThatReachTheBlade) {
  // A blade inside the resting unit box (16 x 16 squares a face), 5 cm under its top face,
  // crosses no edge but the segments from the top face's vertices to their IPs: the clusters of
  // the top face lie outside the swept box, and only their IP reach brings them in.
  struct FineBox {
    GridSource source{V::Zero(), Eigen::Vector3i(4, 4, 4), 0.25};
    TriMesh surface = boxSurface(V::Zero(), V::Ones(), Eigen::Vector3i(16, 16, 16));
    EfgSurfaceCutter cutter{surface, source, EfgSurfaceCutOptions{0.2, 1e-9}};
  } every, bounded;
  BladeSweep s;
  s.start.resize(3, 2);
  s.end.resize(3, 2);
  s.start << 0.6, 0.6, 0.2, 0.8, 0.95, 0.95;
  s.end << 0.4, 0.4, 0.2, 0.8, 0.95, 0.95;
  Eigen::VectorXd rest(3 * bounded.source.numParticles());
  for (int p = 0; p < bounded.source.numParticles(); ++p)
    rest.segment<3>(3 * p) = bounded.source.particleRestPosition(p);
  const std::vector<int> unchanged;
  const EfgParticleMotion motion{rest, rest, unchanged};
  const Eigen::Matrix3Xd X = bounded.cutter.restVertices();
  const EfgSurfaceCutStep b = bounded.cutter.cut(s, X, X, &motion);
  const EfgSurfaceCutStep a = every.cutter.cut(s, X, X);
  EXPECT_EQ(a.crossed_edges + a.ignored_crossings, 0);
  EXPECT_GT(a.remapped.size(), 2u);
  EXPECT_EQ(b.remapped, a.remapped);
}

TEST(EfgSurfaceCutter, SliversKeepTheNearestIpAndTheirRowsFollowItsParticles) {
  // Random crossing sweeps through a sphere leave slivers: vertices whose cut planes admit no
  // IP. Each must hold the nearest IP (ties to the lower index), every other vertex an IP below
  // all its planes; a volume cut changing a sliver's IP refreshes its row.
  const TriMesh sphere = makeIcosphere(2);
  GridSource source(V::Constant(-1.0), Eigen::Vector3i(5, 5, 5), 0.4);
  EfgSurfaceCutter cutter(sphere, source, EfgSurfaceCutOptions{0.3, 1e-9});
  std::mt19937 rng(7);
  const auto below = [&](int ip, const std::vector<CutPlane>& planes) {
    for (const CutPlane& plane : planes)
      if ((source.ipRestPosition(ip) - plane.point).dot(plane.normal) >= 0.0) return false;
    return true;
  };
  const auto nearest = [&](const V& X) {
    int best = 0;
    for (int ip = 1; ip < source.numIntegrationPoints(); ++ip)
      if ((source.ipRestPosition(ip) - X).squaredNorm() <
          (source.ipRestPosition(best) - X).squaredNorm())
        best = ip;
    return best;
  };
  std::vector<int> slivers;
  for (int sweep = 0; sweep < 40; ++sweep) {
    for (const BladeSweep& step : randomCrossingSweeps(rng, 0.3)) {
      const Eigen::Matrix3Xd x = cutter.restVertices();
      cutter.cut(step, x, x);
    }
    const Eigen::Matrix3Xd X = cutter.restVertices();
    slivers.clear();
    for (int v = 0; v < cutter.numVertices(); ++v) {
      if (!cutter.vertexUsed(v)) continue;
      const std::vector<CutPlane>& planes = cutter.vertexPlanes(v);
      bool admits = false;
      for (int ip = 0; ip < source.numIntegrationPoints() && !admits; ++ip)
        admits = below(ip, planes);
      if (admits) {
        ASSERT_TRUE(below(cutter.vertexIp(v), planes)) << "sweep " << sweep << " vertex " << v;
      } else {
        ASSERT_EQ(cutter.vertexIp(v), nearest(X.col(v))) << "sweep " << sweep << " vertex " << v;
        slivers.push_back(v);
      }
    }
  }
  ASSERT_FALSE(slivers.empty());
  // Give the last sliver's IP the particles of a far cell: the sliver keeps its IP, and its row
  // is the source's weights with the new particles.
  const int v = slivers.back(), ip = cutter.vertexIp(v);
  source.setParticles(ip, source.ipParticles(ip == 0 ? 1 : 0));
  const std::vector<int> remapped = cutter.remapVerticesOfIps({ip});
  ASSERT_NE(std::find(remapped.begin(), remapped.end(), v), remapped.end());
  EXPECT_EQ(cutter.vertexIp(v), ip);
  std::vector<int> p, q;
  std::vector<double> w, x;
  cutter.mappingRow(v, p, w);
  source.pointWeights(ip, cutter.restVertices().col(v), q, x);
  EXPECT_EQ(p, q);
  EXPECT_EQ(w, x);
  EXPECT_EQ(p, source.ipParticles(ip == 0 ? 1 : 0));
  std::cout << "[ info ] " << slivers.size() << " sliver vertices after 40 random sweeps\n";
}

TEST(EfgSurfaceCutter, UpdatedTablesCutLikeTablesRebuiltFromScratch) {
  // The same 60 random sweeps (some missing the sphere, cuts completed or left as cracks) through
  // a cutter that updates its tables at each commit and one that rebuilds them: after every step
  // the same triangles in the same order, vertex positions, IPs, cut planes and mapping rows.
  const TriMesh sphere = makeIcosphere(3);
  GridSource source(V::Constant(-1.0), Eigen::Vector3i(5, 5, 5), 0.4);
  EfgSurfaceCutOptions options{0.2, 1e-9};
  EfgSurfaceCutter updated(sphere, source, options);
  options.rebuild_tables = true;
  EfgSurfaceCutter rebuilt(sphere, source, options);
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto unit = [&] { return V(u(rng), u(rng), u(rng)).normalized(); };
  int commits = 0;
  std::vector<int> pu, pr;
  std::vector<double> wu, wr;
  for (int sweep = 0; sweep < 60; ++sweep) {
    const V centre = 0.9 * V(u(rng), u(rng), u(rng)), along = unit();
    V motion = unit();
    motion = (motion - motion.dot(along) * along).normalized();
    const double length = sweep % 3 == 0 ? 0.6 : 4.0;  // short blades leave cracks
    const V a = centre - 0.5 * length * along - 1.5 * motion;
    const V b = centre + 0.5 * length * along - 1.5 * motion;
    for (int k = 0; k < 6; ++k) {
      BladeSweep s{Eigen::Matrix3Xd(3, 2), Eigen::Matrix3Xd(3, 2)};
      s.start << a + 0.5 * k * motion, b + 0.5 * k * motion;
      s.end << a + 0.5 * (k + 1) * motion, b + 0.5 * (k + 1) * motion;
      const Eigen::Matrix3Xd x = updated.restVertices();
      const EfgSurfaceCutStep ru = updated.cut(s, x, x);
      const EfgSurfaceCutStep rr = rebuilt.cut(s, x, x);
      commits += ru.completed || ru.crack ? 1 : 0;
      ASSERT_EQ(ru.crossed_edges, rr.crossed_edges) << "sweep " << sweep << " step " << k;
      ASSERT_EQ(ru.completed, rr.completed);
      ASSERT_EQ(ru.crack, rr.crack);
      ASSERT_EQ(ru.remapped, rr.remapped);
      ASSERT_EQ(updated.triangles(), rebuilt.triangles()) << "sweep " << sweep << " step " << k;
      ASSERT_EQ(updated.restVertices(), rebuilt.restVertices());
    }
  }
  for (int v = 0; v < updated.numVertices(); ++v) {
    ASSERT_EQ(updated.vertexUsed(v), rebuilt.vertexUsed(v));
    if (!updated.vertexUsed(v)) continue;
    EXPECT_EQ(updated.vertexIp(v), rebuilt.vertexIp(v));
    EXPECT_EQ(updated.twin(v), rebuilt.twin(v));
    ASSERT_EQ(updated.vertexPlanes(v).size(), rebuilt.vertexPlanes(v).size());
    for (std::size_t i = 0; i < updated.vertexPlanes(v).size(); ++i) {
      EXPECT_EQ(updated.vertexPlanes(v)[i].point, rebuilt.vertexPlanes(v)[i].point);
      EXPECT_EQ(updated.vertexPlanes(v)[i].normal, rebuilt.vertexPlanes(v)[i].normal);
    }
    updated.mappingRow(v, pu, wu);
    rebuilt.mappingRow(v, pr, wr);
    EXPECT_EQ(pu, pr);
    EXPECT_EQ(wu, wr);
  }
  EXPECT_GT(commits, 25);
  expectClosed(updated);
}

TEST(EfgSurfaceCutter, BadInputGetsAClearError) {
  GridSource source(V::Zero(), Eigen::Vector3i(2, 2, 2), 0.5);
  TriMesh box = boxSurface(V::Zero(), V::Ones(), Eigen::Vector3i(2, 2, 2));
  auto message = [&](const TriMesh& s, const EfgSurfaceCutOptions& o) {
    try {
      EfgSurfaceCutter c(s, source, o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(box, {0.0, 0.0}).find("front_width"), std::string::npos);
  EXPECT_NE(message(box, {0.1, -1.0}).find("tolerance"), std::string::npos);
  TriMesh open = box;
  open.triangles.conservativeResize(3, open.triangles.cols() - 1);
  EXPECT_NE(message(open, {0.1, 0.0}).find("closed"), std::string::npos);
  TriMesh out_of_range = box;
  out_of_range.triangles(0, 0) = 10000;
  EXPECT_NE(message(out_of_range, {0.1, 0.0}).find("outside"), std::string::npos);
  EfgSurfaceCutter cutter(box, source, {0.1, 0.0});
  const BladeSweep s = verticalSweep(0.4, -1, 2, 2, -1, 0.0);
  Eigen::Matrix3Xd x = cutter.restVertices();
  Eigen::Matrix3Xd short_x = x.leftCols(3);
  EXPECT_THROW(cutter.cut(s, short_x, x), std::invalid_argument);
  x(0, 0) = std::nan("");
  EXPECT_THROW(cutter.cut(s, cutter.restVertices(), x), std::invalid_argument);
  // Particle positions of the wrong size or not finite, a changed IP out of range: named.
  const std::vector<int> unchanged;
  const Eigen::Matrix3Xd X = cutter.restVertices();
  Eigen::VectorXd p(3 * source.numParticles());
  for (int a = 0; a < source.numParticles(); ++a)
    p.segment<3>(3 * a) = source.particleRestPosition(a);
  const auto motionMessage = [&](const Eigen::VectorXd& start) {
    const EfgParticleMotion motion{start, p, unchanged};
    try {
      cutter.cut(s, X, X, &motion);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(motionMessage(p.head(6)).find("particle positions have sizes 6"), std::string::npos);
  Eigen::VectorXd bad = p;
  bad(4) = std::numeric_limits<double>::infinity();
  EXPECT_NE(motionMessage(bad).find("particle position"), std::string::npos);
  const std::vector<int> outside = {source.numIntegrationPoints()};
  const EfgParticleMotion motion{p, p, outside};
  EXPECT_THROW(cutter.cut(s, X, X, &motion), std::invalid_argument);
  EXPECT_FALSE(cutter.cutActive());  // rejected before any change
}

TEST(EfgSurfaceCutter, PositionsInTheLeadingColumnsOfALargerBufferCutLikeAMatrix) {
  // A caller's buffer with room to grow: its spare columns hold NaN, which must not be read; a
  // NaN among the vertices' own columns is still refused.
  UnitBox plain, buffered;
  for (int i = 0; i < 40; ++i) {  // through the box, as descendSteps(kTop, 0.05, 40)
    const BladeSweep sweep =
        verticalSweep(kCutX, -0.5, 1.5, kTop - 0.05 * i, kTop - 0.05 * (i + 1), kTilt);
    const Eigen::Matrix3Xd x = buffered.cutter.restVertices();
    const Eigen::Index n = x.cols();
    Eigen::Matrix3Xd buffer = Eigen::Matrix3Xd::Constant(3, 2 * n + 5, std::nan(""));
    buffer.leftCols(n) = x;
    const EfgSurfaceCutStep a = plain.step(sweep);
    const EfgSurfaceCutStep b = buffered.cutter.cut(sweep, buffer.leftCols(n), buffer.leftCols(n));
    ASSERT_EQ(a.crossed_edges, b.crossed_edges) << "step " << i;
    ASSERT_EQ(a.remapped, b.remapped) << "step " << i;
  }
  EXPECT_EQ(plain.cutter.triangles(), buffered.cutter.triangles());
  expectCutInTwoAtCutX(buffered.cutter);
  const Eigen::Matrix3Xd x = buffered.cutter.restVertices();
  Eigen::Matrix3Xd buffer(3, x.cols() + 1);
  buffer.leftCols(x.cols()) = x;
  buffer(2, 0) = std::nan("");
  const Eigen::Index n = x.cols();
  EXPECT_THROW(buffered.cutter.cut(verticalSweep(0.5, -0.5, 1.5, 2.0, -1.0, kTilt),
                                   buffer.leftCols(n), buffer.leftCols(n)),
               std::invalid_argument);
}

TEST(EfgSurfaceCutter, PrintsTheUpdateTimeOnA300kTriangleSphere) {
  const TriMesh sphere = makeIcosphere(7);                                      // 327,680 triangles
  GridSource source(V::Constant(-1.0), Eigen::Vector3i(27, 27, 27), 2.0 / 27);  // 19,683 IPs
  EfgSurfaceCutter cutter(sphere, source, EfgSurfaceCutOptions{0.05, 1e-9});
  // A blade that misses: the broad phase alone.
  const Eigen::Matrix3Xd x = cutter.restVertices();
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 10; ++i) cutter.cut(verticalSweep(0.5, -1.5, 1.5, 3.0, 2.9, 0.0), x, x);
  const double miss =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / 10;
  double total = 0.0, worst = 0.0;
  int steps = 0;
  for (int i = 0; i < 60; ++i) {  // blade descends through the top, 0.02 m a step, stops inside
    const double z = 1.2 - 0.02 * i;
    const BladeSweep s = verticalSweep(0.013, -1.5, 1.5, z, z - 0.02, 0.05);
    const Eigen::Matrix3Xd x = cutter.restVertices();  // static tissue
    const auto t0 = std::chrono::steady_clock::now();
    cutter.cut(s, x, x);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    total += ms;
    worst = std::max(worst, ms);
    ++steps;
  }
  const SurfaceClosure closure = checkSurfaceClosure(cutter.triangles());
  EXPECT_EQ(closure.open_edges, 0);
  EXPECT_EQ(closure.pinched_edges, 0);
  std::cout << "[ info ] broad phase alone (blade misses): " << miss << " ms\n";
  std::cout << "[ info ] 327,680-triangle sphere, 19,683 IPs: cut update mean " << total / steps
            << " ms, worst " << worst << " ms over " << steps << " steps\n";
}

}  // namespace
}  // namespace surgical_sim::core
