#include "surgical_sim/core/contact/normal_derivative.h"

#include <Eigen/Geometry>

namespace surgical_sim::core {
namespace {

/// Parameters / barycentric weights within this of a bound count as on the bound [-].
constexpr double kFeatureTolerance = 1e-12;
/// A sliding direction whose remainder after orthogonalization is shorter than this fraction of
/// its length is already spanned [-].
constexpr double kSpanTolerance = 1e-9;

/// Adds v to the orthonormal basis (columns 0..count-1 of basis) if it is not already spanned.
void addDirection(const Eigen::Vector3d& v, Eigen::Matrix3d& basis, int& count) {
  const double length = v.norm();
  if (count == 3 || !(length > 0.0)) return;
  Eigen::Vector3d rest = v;
  for (int k = 0; k < count; ++k) rest -= basis.col(k).dot(rest) * basis.col(k);
  if (rest.norm() > kSpanTolerance * length) basis.col(count++) = rest.normalized();
}

}  // namespace

Eigen::Matrix3d normalTranslationDerivative(const SegmentTriangleClosest& closest,
                                            const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                            const Eigen::Vector3d& v0, const Eigen::Vector3d& v1,
                                            const Eigen::Vector3d& v2) {
  const Eigen::Vector3d offset = closest.point_triangle - closest.point_segment;
  const double d = offset.norm();
  if (!(d > 0.0)) return Eigen::Matrix3d::Zero();
  Eigen::Matrix3d basis = Eigen::Matrix3d::Zero();
  int count = 0;
  addDirection(offset / d, basis, count);
  if (closest.t > kFeatureTolerance && closest.t < 1.0 - kFeatureTolerance) {
    addDirection(b - a, basis, count);
  }
  const Eigen::Vector3d* vertices[3] = {&v0, &v1, &v2};
  int on_feature[3];
  int feature_size = 0;
  for (int k = 0; k < 3; ++k) {
    if (closest.barycentric[k] > kFeatureTolerance) on_feature[feature_size++] = k;
  }
  for (int k = 1; k < feature_size; ++k) {  // edge: 1 direction; face: 2
    addDirection(*vertices[on_feature[k]] - *vertices[on_feature[0]], basis, count);
  }
  const Eigen::Matrix3d spanned = basis.leftCols(count) * basis.leftCols(count).transpose();
  return -(Eigen::Matrix3d::Identity() - spanned) / d;
}

Eigen::Matrix<double, 3, 9> faceNormalDerivative(const Eigen::Vector3d& v0,
                                                 const Eigen::Vector3d& v1,
                                                 const Eigen::Vector3d& v2) {
  const Eigen::Vector3d e1 = v1 - v0, e2 = v2 - v0;
  const Eigen::Vector3d c = e1.cross(e2);
  const double area2 = c.norm();
  Eigen::Matrix<double, 3, 9> derivative = Eigen::Matrix<double, 3, 9>::Zero();
  if (!(area2 > 0.0)) return derivative;
  const Eigen::Vector3d n = c / area2;
  const Eigen::Matrix3d Q = (Eigen::Matrix3d::Identity() - n * n.transpose()) / area2;
  const auto cross = [](const Eigen::Vector3d& v) {
    Eigen::Matrix3d m;
    m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
    return m;
  };
  derivative.middleCols<3>(0) = Q * cross(v2 - v1);
  derivative.middleCols<3>(3) = -Q * cross(e2);
  derivative.middleCols<3>(6) = Q * cross(e1);
  return derivative;
}

Eigen::Matrix<double, 3, 9> contactNormalNodeDerivative(
    const SegmentTriangleClosest& closest, const Eigen::Vector3d& n, const Eigen::Matrix3d& dn_du,
    const Eigen::Vector3d& v0, const Eigen::Vector3d& v1, const Eigen::Vector3d& v2) {
  if (closest.intersects || !(closest.distance_squared > 0.0) ||
      (closest.barycentric.array() > kFeatureTolerance).all()) {
    const Eigen::Vector3d n_t = (v1 - v0).cross(v2 - v0).normalized();
    return (n.dot(n_t) >= 0.0 ? 1.0 : -1.0) * faceNormalDerivative(v0, v1, v2);
  }
  Eigen::Matrix<double, 3, 9> derivative;
  for (int k = 0; k < 3; ++k) derivative.middleCols<3>(3 * k) = -closest.barycentric[k] * dn_du;
  return derivative;
}

}  // namespace surgical_sim::core
