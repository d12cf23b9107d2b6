#pragma once

#include <Eigen/Core>

#include "surgical_sim/core/contact/closest_points_segment_triangle.h"

namespace surgical_sim::core {

/// Derivative of the contact normal n = (q - c) / d with respect to a rigid translation u of the
/// tool [1/m], for the closest points c on the tool axis [a, b] and q on a fixed triangle
/// (v0, v1, v2), d = |q - c| > 0:
///   dn/du = -P / d,
/// P the orthogonal projector onto the directions normal to n along which neither closest point
/// can slide: c slides along the axis when it is interior to the segment, q along its edge when it
/// is interior to an edge, and within the face plane when it is interior to the face. A tip
/// pressing on a vertex therefore rotates its normal (P = I - n n^T), a face or two crossing
/// edges do not (P = 0). This is the geometric part of the contact stiffness: the force
/// -lambda n of a contact with multiplier lambda [N] changes by lambda P / d per metre of tool
/// motion with lambda held fixed.
Eigen::Matrix3d normalTranslationDerivative(const SegmentTriangleClosest& closest,
                                            const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                            const Eigen::Vector3d& v0, const Eigen::Vector3d& v1,
                                            const Eigen::Vector3d& v2);

/// Derivative of the unit face normal n_t = (v1 - v0) x (v2 - v0) / |...| with respect to the
/// vertex positions (v0, v1, v2) stacked [1/m], 3 x 9: with e1 = v1 - v0, e2 = v2 - v0,
/// c = e1 x e2 and Q = (I - n_t n_t^T) / |c|,
///   dn_t/dv0 = Q [v2 - v1]x,  dn_t/dv1 = -Q [e2]x,  dn_t/dv2 = Q [e1]x.
/// Zero for a degenerate triangle.
Eigen::Matrix<double, 3, 9> faceNormalDerivative(const Eigen::Vector3d& v0,
                                                 const Eigen::Vector3d& v1,
                                                 const Eigen::Vector3d& v2);

/// Derivative of a contact normal n (unit, from the tool to the surface) with respect to the
/// positions of the triangle's three nodes [1/m], 3 x 9, the tool held fixed. A face contact
/// (the segment crosses the triangle, or the closest point is interior to the face) has
/// n = +-n_t: +-faceNormalDerivative. A vertex or edge contact has n along q - c with
/// q = sum_k w_k v_k: moving the nodes moves q relative to the tool, so
/// dn/dv_k = -w_k dn_du (dn_du from normalTranslationDerivative, with n's sign).
Eigen::Matrix<double, 3, 9> contactNormalNodeDerivative(
    const SegmentTriangleClosest& closest, const Eigen::Vector3d& n, const Eigen::Matrix3d& dn_du,
    const Eigen::Vector3d& v0, const Eigen::Vector3d& v1, const Eigen::Vector3d& v2);

}  // namespace surgical_sim::core
