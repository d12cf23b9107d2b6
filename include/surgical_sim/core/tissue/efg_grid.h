#pragma once

#include <Eigen/Core>
#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/efg_options.h"

namespace surgical_sim::core {

/// The two superimposed regular grids of the EFG model.
///
/// Integration cells are cubes of side d = options.spacing starting at the lowest corner of the
/// body's bounding box (a tet mesh or a closed surface), with one integration point (IP) each, at
/// the centroid of the cell's inside volume samples (options.ip_at_centroid) or at the cell centre;
/// DOF particles sit on the grid of side 2 d through the same corner, so each DOF cell holds 2 x 2
/// x 2 integration cells. A cell's volume is d^3 times the fraction of its volume_samples^3
/// regularly spaced sample points (cell-centred sub-grid) that lie in the body; cells with no
/// sample inside are dropped. The particles are the corners of the DOF cells holding a kept IP;
/// they may lie outside the mesh. An IP's neighbours are the 8 corners of its DOF cell, then (for
/// neighbours > 8) the nearest other particles, ties broken by grid index.
struct EfgGrid {
  double spacing = 0.0;                 ///< d [m]
  Eigen::Vector3d origin;               ///< lowest grid corner [m]
  Eigen::Matrix3Xd particles;           ///< particle rest positions [m], 3 x n
  Eigen::Matrix3Xd integration_points;  ///< IP positions [m], 3 x m
  Eigen::VectorXd volumes;              ///< inside volume per IP [m^3], size m, in (0, d^3]
  Eigen::MatrixXi neighbours;           ///< particle indices, options.neighbours x m
  Eigen::Vector3i cells;                ///< integration cells per axis (kept or not)
  /// IP of cell (i, j, k) at i + cells.x (j + cells.y k), or -1 for a dropped cell.
  std::vector<int> ip_of_cell;
};

/// Builds the grids over the Tet4 corners of `mesh` (Tet10 mid-edge nodes are ignored).
/// Allocates; time linear in the number of samples inside the bounding boxes of the tets.
/// @throws std::invalid_argument for invalid options (EfgOptions::validate), an empty mesh or
///         an element index out of range ("mesh.elements"), more than 8e6 integration cells
///         ("efg.spacing" too small) or 5e8 volume samples ("efg.volume_samples") in the bounding
///         box, no cell inside the mesh, or fewer than options.neighbours particles near an IP
///         ("efg.neighbours").
EfgGrid buildEfgGrid(const TetMesh& mesh, const EfgOptions& options);

/// Builds the grids over the closed triangle surface `surface` [m]: as above, with the samples
/// inside the surface (markInsideLattice) instead of inside a tet, over the bounding box of its
/// vertices. Allocates; time linear in the samples and the lattice columns the triangles cover.
/// @throws std::invalid_argument as above, and for a surface without triangles, with a
///         non-finite vertex or a vertex index out of range, or that is not closed
///         (checkSurfaceClosure() finds open edges).
EfgGrid buildEfgGrid(const TriMesh& surface, const EfgOptions& options);

}  // namespace surgical_sim::core
