#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// One contact between a tool and the tissue surface, in the tissue frame S.
/// Constraint row: gap(x) = gap + n^T (sum_k weights_k (x_{nodes_k} - x_free_{nodes_k})) >= 0
/// in the surface vertex positions, i.e. n^T [w0 I, w1 I, w2 I] on the three triangle vertices,
/// mapped to the model's DOFs by the SurfaceMapping (for a tet model the vertices are the surface
/// nodes). A friction extension adds two tangent rows per contact with the same vertex weights
/// (not implemented).
struct ContactPoint {
  int tool = 0;                                           ///< index of the tool in the scene
  int triangle = -1;                                      ///< surface triangle index
  Eigen::Vector3i nodes = Eigen::Vector3i::Constant(-1);  ///< its vertices (mesh node indices)
  Eigen::Vector3d weights = Eigen::Vector3d::Zero();      ///< barycentric weights, >= 0, sum 1
  Eigen::Vector3d p_S = Eigen::Vector3d::Zero();          ///< contact point on the surface [m], S
  Eigen::Vector3d n_S = Eigen::Vector3d::UnitZ();         ///< unit normal from the tool axis to the
                                                          ///< surface point (away from the tool), S
  double gap = 0.0;  ///< distance - radius [m] (negative = penetration)
  /// dn_S/du for a rigid tool translation u [1/m] (normalTranslationDerivative; 0 when n is the
  /// face normal), for the geometric part of the contact stiffness.
  Eigen::Matrix3d dn_du = Eigen::Matrix3d::Zero();
  /// dn_S/d(x_nodes0, x_nodes1, x_nodes2) [1/m], 3 x 9 (contactNormalNodeDerivative): how the
  /// normal turns as the tissue under the tool deforms.
  Eigen::Matrix<double, 3, 9> dn_dx = Eigen::Matrix<double, 3, 9>::Zero();
};

/// Local linear contact model of one tool for the haptic loop, in the tissue frame S: the force
/// of the tissue on the tool near p0 is f(p) = f0 + K (p - p0).
struct ContactLinearization {
  bool in_contact = false;                         ///< at least one active contact / grasp
  Eigen::Vector3d p0_S = Eigen::Vector3d::Zero();  ///< tool tip position [m], S
  Eigen::Vector3d f0_S = Eigen::Vector3d::Zero();  ///< force of the tissue on the tool [N], S
  Eigen::Matrix3d K_S = Eigen::Matrix3d::Zero();   ///< df/dp [N/m], S, 3x3 (not symmetric
                                                   ///< near vertices and edges or at a force cap)
  int contacts = 0;                                ///< number of active contacts
};

}  // namespace surgical_sim::core
