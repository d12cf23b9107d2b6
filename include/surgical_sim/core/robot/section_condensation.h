#pragma once

#include <Eigen/Core>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {

/// 6x6 compliance of an inter-vertebra section (Bosman eqs 5.2-5.11, digest corrections).
///
/// The section mesh is given in the frame P of its proximal rigid node (axis +x). The nodes with
/// x <= proximal_face_x (+ 1e-9 relative) are clamped (proximal rigid node fixed); the nodes with
/// x >= distal_face_x are tied rigidly to the distal rigid node at p_PD by
/// dp = dx + dtheta x (p - p_PD). The linear corotational stiffness K_v at rest is condensed onto
/// the distal node's 6 DOFs (dx, dtheta) by one CHOLMOD factorization of the mixed node-rigid
/// stiffness and 6 solves with unit loads.
/// @param mesh Tet4 or Tet10 section mesh [m], frame P.
/// @param material section material.
/// @param proximal_face_x x of the clamped face [m], frame P.
/// @param distal_face_x x of the face tied to the distal rigid node [m], > proximal_face_x.
/// @param p_PD distal rigid node position [m], frame P.
/// @return C, symmetric positive definite, rows/cols (force x,y,z, torque x,y,z) -> (dx [m],
///         dtheta [rad]), expressed in frame P.
/// @throws std::invalid_argument if a face holds no node, or the condensed matrix is not positive
///         definite (a mesh that does not connect the two faces).
Eigen::Matrix<double, 6, 6> condenseSection(const TetMesh& mesh, const Material& material,
                                            double proximal_face_x, double distal_face_x,
                                            const Eigen::Vector3d& p_PD);

}  // namespace surgical_sim::core
