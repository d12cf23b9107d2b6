#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "surgical_sim/core/robot/rigid_node_pose.h"

namespace surgical_sim::core {

/// Which tangent EquivalentSpring::evaluate returns.
enum class SpringTangent {
  Exact,        ///< -dF/dq exactly (geometric terms included; not symmetric away from rest)
  GaussNewton,  ///< J^T S J: symmetric positive semi-definite (rigid modes in its null space)
};

/// Corotated equivalent spring between two consecutive rigid nodes A (proximal) and B (distal)
/// (Bosman eqs 5.12-5.18 with the digest's corrections).
///
/// Relative displacement in A's frame, dq = (R_A^T (p_B - p_A) - d_rest,
/// log(Q_rest^T R_A^T R_B)), energy E = 1/2 dq^T C^-1 dq, restoring generalized force
/// F = -dE/dq = -J^T C^-1 dq with J = d(dq)/d(dx_A, dtheta_A, dx_B, dtheta_B). Invariant under
/// rigid motions of the pair. At rest the stiffness is exactly the condensed C^-1 on B with A
/// clamped.
class EquivalentSpring {
 public:
  /// @param compliance C [m/N, rad/(N m)], 6x6 symmetric positive definite, frame A at rest.
  /// @param d_rest R_A^T (p_B - p_A) at rest [m].
  /// @param q_rest R_A^T R_B at rest (unit quaternion).
  /// @throws std::invalid_argument "equivalent_spring.compliance" if C is not finite, symmetric
  ///         and positive definite.
  EquivalentSpring(const Eigen::Matrix<double, 6, 6>& compliance, const Eigen::Vector3d& d_rest,
                   const Eigen::Quaterniond& q_rest);

  /// Energy [J] at poses a, b. If force: generalized force on (p_A, theta_A, p_B, theta_B)
  /// [N, N m], frame B (robot_base), shape 12. If stiffness: -dF/dq, shape 12x12. Allocation-free.
  double evaluate(const RigidNodePose& a, const RigidNodePose& b,
                  Eigen::Matrix<double, 12, 1>* force, Eigen::Matrix<double, 12, 12>* stiffness,
                  SpringTangent tangent) const;

  /// C^-1 [N/m, N m/rad].
  const Eigen::Matrix<double, 6, 6>& stiffness() const { return stiffness_; }

 private:
  Eigen::Matrix<double, 6, 6> stiffness_;
  Eigen::Vector3d d_rest_;
  Eigen::Matrix3d r_rest_;
};

}  // namespace surgical_sim::core
