#pragma once

#include <Eigen/Core>
#include <functional>
#include <random>
#include <vector>

#include "surgical_sim/core/connective/rigid_node_model.h"
#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {

/// Rigid nodes at rest and their samples: the input of RigidNodeModel.
struct RigidNodeLayout {
  RigidNodeConfiguration rest;
  std::vector<RigidNodeSample> samples;
};

/// Mesh-based layout of a Tet4 mesh of the connective layer: one rigid node per mesh node (rest
/// orientation identity), 4 samples per tet at the points of the degree-2 Gauss rule
/// (barycentric 0.5854, 0.1382, 0.1382, 0.1382 and permutations), each with a quarter of the tet's
/// volume and linear barycentric weights on the tet's corners.
/// @throws std::invalid_argument if the mesh is not Tet4, empty, or has a degenerate tet
RigidNodeLayout tetMeshLayout(const TetMesh& mesh, const Material& material);

/// Grid layout with trilinear weights (8 neighbours per sample): rigid nodes (rest orientation
/// identity) at the points min_corner + size (i, j, k) / (nodes - 1) of a regular grid;
/// per grid cell, 27 samples at the 3 x 3 x 3 Gauss-Legendre points (volume: the cell's volume
/// times the product of the rule's weights / 8). Fewer samples leave hourglass modes: the
/// skinned displacement sum_i w_i (dx_i + dtheta_i x (p - x_i)) is quadratic per axis, which
/// the 2 x 2 x 2 rule does not integrate exactly. Samples outside `inside` (when
/// given) are dropped, and so are rigid nodes left without samples; if `volume` > 0 the sample
/// volumes are then scaled to sum to it (the volume of the body `inside` describes).
/// @param nodes rigid nodes per axis, each >= 2
/// @throws std::invalid_argument for a parameter out of range or if no sample is inside
RigidNodeLayout trilinearGridLayout(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& size,
                                    const Eigen::Vector3i& nodes, const Material& material,
                                    const std::function<bool(const Eigen::Vector3d&)>& inside = {},
                                    double volume = 0.0);

/// Meshless layout inside a closed, outward-oriented triangle surface (Bosman's voxel-free
/// variant): rigid nodes and samples by Poisson-disk dart throwing in the surface's bounding box
/// (a point is kept if it is inside, by winding number, and at least its spacing away from the
/// points kept before; sampling stops after 30 n_kept + 1000 consecutive rejections), nodes at
/// node_spacing, samples at sample_spacing, each sample with Shepard weights (exponent 2) on its
/// `neighbours` nearest nodes and volume V / samples (V the enclosed volume). Nodes no sample
/// uses are dropped; rest orientations are the identity.
/// @param surface closed (checkSurfaceClosure: no open edge) with positive enclosed volume [m]
/// @param node_spacing, sample_spacing [m], finite, 0 < sample_spacing < node_spacing
/// @param neighbours in [1, kMaxSampleNeighbours] and at most the number of nodes placed
/// @param rng the only source of randomness (same seed, same layout)
/// @throws std::invalid_argument naming the parameter, or if the surface is open, encloses no
///         volume or too few points fit
RigidNodeLayout poissonDiskLayout(const TriMesh& surface, double node_spacing,
                                  double sample_spacing, int neighbours, const Material& material,
                                  std::mt19937& rng);

}  // namespace surgical_sim::core
