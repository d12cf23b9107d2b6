// Procedural closed surfaces (icosphere, liver-like body) and the lattice inside test.
#include "surgical_sim/core/mesh/surface_generators.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <stdexcept>

#include "surgical_sim/core/mesh/surface_closure.h"
#include "surgical_sim/core/mesh/surface_inside.h"

namespace surgical_sim::core {
namespace {

/// Smallest triangle area of the surface [m^2].
double minArea(const TriMesh& m) {
  double smallest = INFINITY;
  for (Eigen::Index t = 0; t < m.triangles.cols(); ++t) {
    const Eigen::Vector3d a = m.vertices.col(m.triangles(0, t));
    smallest = std::min(smallest, 0.5 * (m.vertices.col(m.triangles(1, t)) - a)
                                            .cross(m.vertices.col(m.triangles(2, t)) - a)
                                            .norm());
  }
  return smallest;
}

/// Volume of the lattice points of pitch h inside `m`, over its bounding box [m^3].
double latticeVolume(const TriMesh& m, double h) {
  const Eigen::Vector3d lo = m.vertices.rowwise().minCoeff();
  const Eigen::Vector3d hi = m.vertices.rowwise().maxCoeff();
  const Eigen::Vector3i count = ((hi - lo) / h).array().ceil().cast<int>();
  const auto inside = markInsideLattice(m, lo, h, count);
  double n = 0.0;
  for (const auto b : inside) n += b;
  return n * h * h * h;
}

TEST(Icosphere, ClosedManifoldOnTheUnitSphereAndConvergingToItsVolume) {
  double previous_error = INFINITY;
  for (int s = 0; s <= 4; ++s) {
    const TriMesh m = makeIcosphere(s);
    const int p = 1 << (2 * s);
    EXPECT_EQ(m.vertices.cols(), 10 * p + 2);
    EXPECT_EQ(m.triangles.cols(), 20 * p);
    const SurfaceClosure c = checkSurfaceClosure(m.triangles);
    EXPECT_EQ(c.open_edges, 0);
    EXPECT_EQ(c.pinched_edges, 0);
    EXPECT_NEAR(m.vertices.colwise().norm().minCoeff(), 1.0, 1e-15);
    EXPECT_NEAR(m.vertices.colwise().norm().maxCoeff(), 1.0, 1e-15);
    // Outward: positive volume, from below towards the ball's.
    const double error = 4.0 * M_PI / 3.0 - enclosedVolume(m);
    EXPECT_GT(error, 0.0);
    EXPECT_LT(error, 0.35 * previous_error);  // O(h^2): about a quarter per subdivision
    previous_error = error;
  }
  EXPECT_LT(previous_error / (4.0 * M_PI / 3.0), 0.003);
}

TEST(LiverSurface, ClosedManifoldLiverLikeBody) {
  const Eigen::Vector3d semi_axes(0.09, 0.06, 0.04);
  const TriMesh m = makeLiverSurface(semi_axes, 5);
  EXPECT_EQ(m.triangles.cols(), 20480);
  const SurfaceClosure c = checkSurfaceClosure(m.triangles);
  EXPECT_EQ(c.open_edges, 0);
  EXPECT_EQ(c.pinched_edges, 0);
  EXPECT_GT(minArea(m), 1e-8);  // no degenerate triangle (mean area ~2e-6 m^2)
  const Eigen::Vector3d lo = m.vertices.rowwise().minCoeff();
  const Eigen::Vector3d hi = m.vertices.rowwise().maxCoeff();
  // x spans the full length; the right lobe (x > 0) is thicker than the left one.
  EXPECT_NEAR(lo.x(), -semi_axes.x(), 1e-3 * semi_axes.x());
  EXPECT_NEAR(hi.x(), semi_axes.x(), 1e-3 * semi_axes.x());
  EXPECT_LE(hi.z(), semi_axes.z());
  EXPECT_GT(hi.z(), 0.6 * semi_axes.z());
  EXPECT_GT(lo.z(), -0.6 * semi_axes.z());  // flatter underside
  std::cout << "liver extents " << lo.transpose() << " .. " << hi.transpose() << " volume "
            << enclosedVolume(m) << "\n";
  const auto thickness = [&](double x) {
    double top = -INFINITY, bottom = INFINITY;
    for (Eigen::Index v = 0; v < m.vertices.cols(); ++v)
      if (std::abs(m.vertices(0, v) - x) < 0.005) {
        top = std::max(top, m.vertices(2, v));
        bottom = std::min(bottom, m.vertices(2, v));
      }
    return top - bottom;
  };
  EXPECT_GT(thickness(0.04), 1.5 * thickness(-0.04));
  // Outward, and the lattice inside test agrees with the enclosed volume.
  const double volume = enclosedVolume(m);
  EXPECT_GT(volume, 0.3 * (4.0 / 3.0) * M_PI * semi_axes.prod());
  EXPECT_NEAR(latticeVolume(m, 0.001), volume, 0.01 * volume);
}

TEST(LiverSurface, RejectsBadParameters) {
  EXPECT_THROW(makeLiverSurface(Eigen::Vector3d(0.1, 0.0, 0.1), 3), std::invalid_argument);
  EXPECT_THROW(makeLiverSurface(Eigen::Vector3d(0.1, 0.1, 0.1), -1), std::invalid_argument);
  EXPECT_THROW(makeIcosphere(kMaxSurfaceSubdivisions + 1), std::invalid_argument);
}

TEST(MarkInsideLattice, SphereVolumeConvergesUnderRefinement) {
  const TriMesh ball = makeIcosphere(6);
  const double volume = enclosedVolume(ball);
  double previous = INFINITY;
  for (const double h : {0.2, 0.1, 0.05, 0.025}) {
    const double error = std::abs(latticeVolume(ball, h) - volume) / volume;
    EXPECT_LT(error, 1.2 * previous);
    previous = error;
  }
  EXPECT_LT(previous, 0.005);
}

TEST(MarkInsideLattice, ColumnsThroughEdgesAndVerticesCountOnce) {
  // The unit cube, 12 triangles: lattice columns run exactly through its vertical faces, edges,
  // corners and the face diagonals. The perturbation (+e, +e^2) keeps x = 0 and y = 0 inside and
  // x = 1, y = 1 outside; z = 0 and z = 1 are on crossed faces and inside.
  TriMesh cube;
  cube.vertices.resize(3, 8);
  for (int v = 0; v < 8; ++v) cube.vertices.col(v) << (v & 1), ((v >> 1) & 1), ((v >> 2) & 1);
  cube.triangles.resize(3, 12);
  cube.triangles << 0, 0, 4, 4, 0, 0, 2, 2, 0, 0, 1, 1,  //
      2, 3, 5, 7, 1, 5, 6, 7, 4, 6, 3, 7,                //
      3, 1, 7, 6, 5, 4, 7, 3, 6, 2, 7, 5;
  ASSERT_EQ(checkSurfaceClosure(cube.triangles).open_edges, 0);
  ASSERT_NEAR(enclosedVolume(cube), 1.0, 1e-15);
  const auto inside = markInsideLattice(cube, Eigen::Vector3d::Constant(-0.375), 0.25,
                                        Eigen::Vector3i::Constant(7));
  int count = 0;
  for (int k = 0; k < 7; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 7; ++i) {
        const bool in = inside[static_cast<std::size_t>(i + 7 * (j + 7 * k))];
        // Points at -0.25 + 0.25 i: inside for x, y in [0, 0.75] and z in [0, 1].
        const bool expected = i >= 1 && i <= 4 && j >= 1 && j <= 4 && k >= 1 && k <= 5;
        EXPECT_EQ(in, expected) << i << " " << j << " " << k;
        count += in;
      }
  EXPECT_EQ(count, 80);
}

TEST(MarkInsideLattice, RejectsBadInput) {
  const TriMesh ball = makeIcosphere(1);
  const Eigen::Vector3d o = Eigen::Vector3d::Constant(-1.0);
  EXPECT_THROW(markInsideLattice(ball, o, 0.0, Eigen::Vector3i::Constant(4)),
               std::invalid_argument);
  EXPECT_THROW(markInsideLattice(ball, o, 0.5, Eigen::Vector3i(4, 0, 4)), std::invalid_argument);
  TriMesh bad = ball;
  bad.triangles(1, 3) = 99;
  EXPECT_THROW(markInsideLattice(bad, o, 0.5, Eigen::Vector3i::Constant(4)), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core

namespace surgical_sim::core {
namespace {

TEST(Cylinder, ClosedOutwardAndEnclosingThePolygonPrismVolume) {
  const double r = 0.02, length = 0.1;
  const int segments = 48, rings = 5;
  const TriMesh m = makeCylinder(r, length, segments, rings);
  EXPECT_EQ(m.vertices.cols(), segments * (rings + 1) + 2);
  EXPECT_EQ(m.triangles.cols(), 2 * segments * (rings + 1));
  const SurfaceClosure c = checkSurfaceClosure(m.triangles);
  EXPECT_EQ(c.open_edges, 0);
  EXPECT_EQ(c.pinched_edges, 0);
  const double prism = 0.5 * segments * r * r * std::sin(2.0 * M_PI / segments) * length;
  EXPECT_NEAR(enclosedVolume(m), prism, 1e-12 * prism);
  EXPECT_NEAR(m.vertices.row(2).minCoeff(), -0.5 * length, 1e-15);
  EXPECT_NEAR(m.vertices.row(2).maxCoeff(), 0.5 * length, 1e-15);
}

TEST(Torus, ClosedOutwardAndConvergingToItsVolume) {
  const double R = 0.05, r = 0.015;
  const double exact = 2.0 * M_PI * M_PI * R * r * r;
  double previous = INFINITY;
  for (int s : {12, 24, 48}) {
    const TriMesh m = makeTorus(R, r, 2 * s, s);
    EXPECT_EQ(m.triangles.cols(), 4 * s * s);
    const SurfaceClosure c = checkSurfaceClosure(m.triangles);
    EXPECT_EQ(c.open_edges, 0);
    EXPECT_EQ(c.pinched_edges, 0);
    const double error = std::abs(enclosedVolume(m) - exact) / exact;
    EXPECT_LT(error, 0.35 * previous);  // O(h^2)
    previous = error;
  }
  EXPECT_LT(previous, 0.005);
}

TEST(CylinderAndTorus, BadParametersAreNamed) {
  const auto message = [](auto&& make) {
    try {
      make();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message([] { makeCylinder(-1.0, 1.0, 8, 1); }).find("radius"), std::string::npos);
  EXPECT_NE(message([] { makeCylinder(1.0, NAN, 8, 1); }).find("length"), std::string::npos);
  EXPECT_NE(message([] { makeCylinder(1.0, 1.0, 2, 1); }).find("segments"), std::string::npos);
  EXPECT_NE(message([] { makeCylinder(1.0, 1.0, 8, 0); }).find("rings"), std::string::npos);
  EXPECT_NE(message([] { makeTorus(0.5, 1.0, 8, 8); }).find("major"), std::string::npos);
  EXPECT_NE(message([] { makeTorus(2.0, 0.0, 8, 8); }).find("minor"), std::string::npos);
  EXPECT_NE(message([] { makeTorus(2.0, 1.0, 8, 5000); }).find("minor_segments"),
            std::string::npos);
}

}  // namespace
}  // namespace surgical_sim::core
