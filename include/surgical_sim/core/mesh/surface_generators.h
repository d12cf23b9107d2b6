#pragma once

#include <Eigen/Core>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Procedural closed triangle surfaces, in metres, outward-oriented (counter-clockwise seen from
/// outside), closed and edge-manifold (every edge in exactly two triangles, used once in each
/// direction).

/// Largest subdivision level of makeIcosphere() / makeLiverSurface() (20 4^8 = 1.3 M triangles).
constexpr int kMaxSurfaceSubdivisions = 8;

/// Unit sphere: the regular icosahedron with every triangle split `subdivisions` times into 4
/// (edge midpoints shared by both triangles of the edge), all vertices projected onto the sphere.
/// @param subdivisions in [0, kMaxSurfaceSubdivisions]; the surface has 10 4^s + 2 vertices and
///        20 4^s triangles.
/// @throws std::invalid_argument naming "subdivisions" and its range.
TriMesh makeIcosphere(int subdivisions);

/// Liver-like closed surface: a smooth lobed, wedge-shaped body of extents about
/// [-a, a] x [-b, b] x [-c, c] (semi_axes (a, b, c)), with a thick rounded right lobe (x > 0), a
/// thin left lobe (x < 0), a domed top, a flatter underside and a notch in the top between the
/// lobes. Each vertex u of makeIcosphere(subdivisions) is mapped in four steps:
///   1. notch (radial, so the surface stays star-shaped about the origin):
///        p = u (1 - 0.2 exp(-((u_x + 0.25) / 0.2)^2) (1 + u_z) / 2);
///   2. thickness, tapering towards the left lobe and flatter below (|p_z| <= 1, g increasing):
///        p_z <- (0.65 + 0.35 p_x) g(p_z),  g(z) = (z + 0.35 z^2) / 1.35;
///   3. curve in plan: p_y <- p_y - 0.25 p_x^2;
///   4. scale: v = (a p_x, b p_y, c p_z).
/// Every step is one-to-one with a positive Jacobian (the radial factor is >= 0.8, g' > 0 on
/// [-1, 1], the thickness factor is >= 0.3, a shear, a positive scaling), so the surface has the
/// sphere's connectivity, is closed, edge-manifold, outward-oriented and free of
/// self-intersections. Its top is at most c high, its underside at least -c/1.35 x thickness.
/// @param semi_axes (a, b, c) [m], each finite and > 0.
/// @param subdivisions as makeIcosphere() (5: 20,480 triangles).
/// @throws std::invalid_argument naming the offending parameter.
TriMesh makeLiverSurface(const Eigen::Vector3d& semi_axes, int subdivisions);

/// Most segments per circle of makeCylinder() / makeTorus() [-].
constexpr int kMaxSurfaceSegments = 4096;

/// Closed circular cylinder of `radius` and `length` [m] along z, centred at the origin: `segments`
/// vertices per circle (angle 2 pi i / segments from +x), `rings` + 1 circles from z = -length/2
/// to length/2, each end capped by a fan around its centre vertex. segments (rings + 1) + 2
/// vertices, 2 segments (rings + 1) triangles.
/// @param radius, length finite and > 0 [m]; segments in [3, kMaxSurfaceSegments]; rings in
///        [1, kMaxSurfaceSegments].
/// @throws std::invalid_argument naming the offending parameter and its range.
TriMesh makeCylinder(double radius, double length, int segments, int rings);

/// Closed torus around the z axis, centred at the origin: tube centre circle of radius `major`
/// in the xy-plane, tube radius `minor` [m]; vertex (i, j) at angles u = 2 pi i / major_segments
/// around z and v = 2 pi j / minor_segments around the tube,
/// ((major + minor cos v) cos u, (major + minor cos v) sin u, minor sin v).
/// 2 major_segments minor_segments triangles.
/// @param major, minor finite, 0 < minor < major [m]; segment counts in [3, kMaxSurfaceSegments].
/// @throws std::invalid_argument naming the offending parameter and its range.
TriMesh makeTorus(double major, double minor, int major_segments, int minor_segments);

}  // namespace surgical_sim::core
