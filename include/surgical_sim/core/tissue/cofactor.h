#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace surgical_sim::core {

/// Cofactor matrix cof F = det(F) F^-T = d(det F)/dF of a 3 x 3 matrix: columns f1 x f2,
/// f2 x f0, f0 x f1 (f_i the columns of F), so det F = f0 . (cof F).col(0).
inline Eigen::Matrix3d cofactor(const Eigen::Matrix3d& F) {
  Eigen::Matrix3d C;
  C.col(0) = F.col(1).cross(F.col(2));
  C.col(1) = F.col(2).cross(F.col(0));
  C.col(2) = F.col(0).cross(F.col(1));
  return C;
}

}  // namespace surgical_sim::core
