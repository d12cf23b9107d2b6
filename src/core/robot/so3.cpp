#include "surgical_sim/core/robot/so3.h"

#include <cmath>

namespace surgical_sim::core {
namespace {

/// c(theta) = 1/theta^2 - (1 + cos theta) / (2 theta sin theta), the [phi]x^2 coefficient of
/// Jr^-1, and c'(theta) / theta.
void inverseJacobianCoefficients(double theta, double* c, double* dc_over_theta) {
  if (theta < 1e-3) {
    const double t2 = theta * theta;
    *c = 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0;
    *dc_over_theta = 1.0 / 360.0 + t2 / 7560.0;
    return;
  }
  const double half = 0.5 * theta;
  const double cot_half = std::cos(half) / std::sin(half);
  const double csc2_half = 1.0 / (std::sin(half) * std::sin(half));
  *c = 1.0 / (theta * theta) - cot_half / (2.0 * theta);
  const double dh = -(theta * csc2_half + 2.0 * cot_half) / (4.0 * theta * theta);
  *dc_over_theta = (-2.0 / (theta * theta * theta) - dh) / theta;
}

}  // namespace

Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d s;
  s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return s;
}

Eigen::Quaterniond expRotation(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  if (theta < 1e-12)
    return Eigen::Quaterniond(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z()).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(theta, phi / theta));
}

Eigen::Vector3d logRotation(const Eigen::Matrix3d& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  if (s < 1e-12) return 2.0 * q.vec() / q.w();
  const double theta = 2.0 * std::atan2(s, q.w());
  return q.vec() * (theta / s);
}

Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& phi) {
  double c = 0.0, dc = 0.0;
  inverseJacobianCoefficients(phi.norm(), &c, &dc);
  const Eigen::Matrix3d S = skew(phi);
  return Eigen::Matrix3d::Identity() + 0.5 * S + c * S * S;
}

Eigen::Matrix3d rightJacobianInverseTransposeDerivative(const Eigen::Vector3d& phi,
                                                        const Eigen::Vector3d& g) {
  // b = g - 1/2 phi x g + c(theta) (phi (phi.g) - theta^2 g).
  const double theta = phi.norm();
  double c = 0.0, dc_over_theta = 0.0;
  inverseJacobianCoefficients(theta, &c, &dc_over_theta);
  const Eigen::Vector3d w = phi * phi.dot(g) - theta * theta * g;
  return 0.5 * skew(g) +
         c * (phi * g.transpose() + phi.dot(g) * Eigen::Matrix3d::Identity() -
              2.0 * g * phi.transpose()) +
         dc_over_theta * w * phi.transpose();
}

}  // namespace surgical_sim::core
