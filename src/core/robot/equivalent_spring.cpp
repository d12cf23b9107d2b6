#include "surgical_sim/core/robot/equivalent_spring.h"

#include <Eigen/Cholesky>
#include <stdexcept>

#include "surgical_sim/core/robot/so3.h"

namespace surgical_sim::core {

EquivalentSpring::EquivalentSpring(const Eigen::Matrix<double, 6, 6>& compliance,
                                   const Eigen::Vector3d& d_rest, const Eigen::Quaterniond& q_rest)
    : d_rest_(d_rest), r_rest_(q_rest.normalized().toRotationMatrix()) {
  const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(compliance);
  if (!compliance.allFinite() ||
      (compliance - compliance.transpose()).norm() > 1e-9 * compliance.norm() ||
      llt.info() != Eigen::Success)
    throw std::invalid_argument(
        "equivalent_spring.compliance must be finite, symmetric and positive definite");
  stiffness_ = llt.solve(Eigen::Matrix<double, 6, 6>::Identity());
  stiffness_ = 0.5 * (stiffness_ + stiffness_.transpose()).eval();
}

double EquivalentSpring::evaluate(const RigidNodePose& a, const RigidNodePose& b,
                                  Eigen::Matrix<double, 12, 1>* force,
                                  Eigen::Matrix<double, 12, 12>* stiffness,
                                  SpringTangent tangent) const {
  const Eigen::Matrix3d Ra = a.q_BN.toRotationMatrix();
  const Eigen::Matrix3d Rb = b.q_BN.toRotationMatrix();
  const Eigen::Vector3d d = b.p_BN - a.p_BN;
  Eigen::Matrix<double, 6, 1> dq;
  dq.head<3>() = Ra.transpose() * d - d_rest_;
  dq.tail<3>() = logRotation(r_rest_.transpose() * Ra.transpose() * Rb);
  const Eigen::Matrix<double, 6, 1> g = stiffness_ * dq;
  const double energy = 0.5 * dq.dot(g);
  if (!force && !stiffness) return energy;

  // J = d(dq)/dq, columns (dx_A, dtheta_A, dx_B, dtheta_B).
  const Eigen::Matrix3d A = rightJacobianInverse(dq.tail<3>()) * Rb.transpose();
  Eigen::Matrix<double, 6, 12> J = Eigen::Matrix<double, 6, 12>::Zero();
  J.block<3, 3>(0, 0) = -Ra.transpose();
  J.block<3, 3>(0, 3) = Ra.transpose() * skew(d);
  J.block<3, 3>(0, 6) = Ra.transpose();
  J.block<3, 3>(3, 3) = -A;
  J.block<3, 3>(3, 9) = A;
  if (force) *force = -J.transpose() * g;
  if (!stiffness) return energy;
  *stiffness = J.transpose() * stiffness_ * J;
  if (tangent == SpringTangent::GaussNewton) return energy;

  // Geometric part: d(J^T g)/dq with g held fixed.
  const Eigen::Vector3d fa = Ra * g.head<3>();
  const Eigen::Vector3d jb = rightJacobianInverse(dq.tail<3>()).transpose() * g.tail<3>();
  const Eigen::Matrix3d Sa = skew(fa), Sd = skew(d), Sb = skew(Rb * jb);
  const Eigen::Matrix<double, 3, 12> dJb =
      Rb * rightJacobianInverseTransposeDerivative(dq.tail<3>(), g.tail<3>()) * J.bottomRows<3>();
  Eigen::Matrix<double, 12, 12>& K = *stiffness;
  K.block<3, 3>(0, 3) += Sa;
  K.block<3, 3>(6, 3) -= Sa;
  K.block<3, 3>(3, 0) -= Sa;
  K.block<3, 3>(3, 6) += Sa;
  K.block<3, 3>(3, 3) += Sd * Sa;
  K.block<3, 3>(3, 9) += Sb;
  K.middleRows<3>(3) -= dJb;
  K.block<3, 3>(9, 9) -= Sb;
  K.middleRows<3>(9) += dJb;
  return energy;
}

}  // namespace surgical_sim::core
