#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace surgical_sim::core {

/// Stateless SO(3) helpers for rotation vectors phi [rad] (axis * angle, shape 3).

/// Cross-product matrix: skew(a) b = a x b.
Eigen::Matrix3d skew(const Eigen::Vector3d& a);
/// exp(phi) as a unit quaternion.
Eigen::Quaterniond expRotation(const Eigen::Vector3d& phi);
/// log(R) as a rotation vector with angle in [0, pi]; robust near 0 and pi.
Eigen::Vector3d logRotation(const Eigen::Matrix3d& R);
/// Inverse right Jacobian: log(exp(phi) exp(w)) = phi + Jr^-1(phi) w + O(|w|^2).
Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& phi);
/// d(Jr^-1(phi)^T g)/d(phi) for a fixed vector g (3x3).
Eigen::Matrix3d rightJacobianInverseTransposeDerivative(const Eigen::Vector3d& phi,
                                                        const Eigen::Vector3d& g);

}  // namespace surgical_sim::core
