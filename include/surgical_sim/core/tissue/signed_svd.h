#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Rotation-preserving ("signed") SVD F = U diag(s) V^T of a 3 x 3 matrix.
struct SignedSvd {
  Eigen::Matrix3d U;  ///< rotation, det U = +1
  Eigen::Vector3d s;  ///< signed singular values, |s0| >= |s1| >= |s2|; only s2 may be negative
  Eigen::Matrix3d V;  ///< rotation, det V = +1
};

/// Signed SVD of F: U and V are proper rotations and, when det F < 0, the singular value of
/// smallest magnitude carries the sign, so that R = U V^T is the rotation closest to F even for
/// inverted elements. Allocation-free.
SignedSvd computeSignedSvd(const Eigen::Matrix3d& F);

/// The rotation R = U V^T of computeSignedSvd(F) (equal to round-off), a few times cheaper for the
/// usual well-conditioned F with det F > 0 (Newton's polar iteration); inverted, singular or badly
/// conditioned F fall back to the signed SVD. Allocation-free.
Eigen::Matrix3d computeSignedRotation(const Eigen::Matrix3d& F);

}  // namespace surgical_sim::core
