#pragma once

#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// Tet4 mesh of a (possibly tapered) tube along +x: rings of nodes at the axial stations, radius
/// from inner_radius to the outer radius, which varies linearly from outer_radius_start at
/// stations.front() to outer_radius_end at stations.back(). Each (radial, angular, axial) cell is
/// split into 6 tetrahedra around its diagonal in (r, theta, x) index space, which keeps the mesh
/// conforming, also across the angular seam. All elements positively oriented.
/// Node (station s, radial ring i, angular column j) has index (s (radial_layers + 1) + i)
/// circumferential_segments + j and position (x_s, r cos(2 pi j / C), r sin(2 pi j / C)).
/// @param stations strictly increasing axial positions [m], at least 2, finite.
/// @param inner_radius bore radius [m], > 0.
/// @param outer_radius_start outer radius at stations.front() [m], > inner_radius.
/// @param outer_radius_end outer radius at stations.back() [m], > inner_radius.
/// @param radial_layers element layers through the wall [-], >= 1.
/// @param circumferential_segments element columns around the axis [-], >= 6.
/// @throws std::invalid_argument naming the offending parameter.
TetMesh makeTubeMesh(const std::vector<double>& stations, double inner_radius,
                     double outer_radius_start, double outer_radius_end, int radial_layers,
                     int circumferential_segments);

}  // namespace surgical_sim::core
