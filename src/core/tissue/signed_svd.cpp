#include "surgical_sim/core/tissue/signed_svd.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <utility>

namespace surgical_sim::core {
namespace {

constexpr int kMaxSweeps = 12;
constexpr double kOffDiagonalTolerance = 1e-15;  // relative to the largest diagonal entry

// One classical Jacobi rotation in the (p, q) plane annihilating A(p, q) of the symmetric A;
// r is the third index. Accumulates the rotation into the columns of V.
void rotate(Eigen::Matrix3d& A, Eigen::Matrix3d& V, int p, int q, int r, double tolerance) {
  const double apq = A(p, q);
  if (std::abs(apq) <= tolerance) return;
  const double theta = (A(q, q) - A(p, p)) / (2.0 * apq);
  const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
  const double c = 1.0 / std::sqrt(t * t + 1.0);
  const double s = t * c;
  A(p, p) -= t * apq;
  A(q, q) += t * apq;
  A(p, q) = A(q, p) = 0.0;
  const double arp = A(r, p);
  const double arq = A(r, q);
  A(r, p) = A(p, r) = c * arp - s * arq;
  A(r, q) = A(q, r) = s * arp + c * arq;
  const Eigen::Vector3d vp = V.col(p);
  V.col(p) = c * vp - s * V.col(q);
  V.col(q) = s * vp + c * V.col(q);
}

// Cyclic Jacobi eigen-decomposition of the symmetric 3 x 3 matrix A = F^T F: on return A is
// diagonal and V (a product of plane rotations, det V = +1) holds the eigenvectors.
void jacobiEigen(Eigen::Matrix3d& A, Eigen::Matrix3d& V) {
  V.setIdentity();
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    const double off = std::max({std::abs(A(0, 1)), std::abs(A(0, 2)), std::abs(A(1, 2))});
    const double tolerance = kOffDiagonalTolerance * A.diagonal().cwiseAbs().maxCoeff();
    if (off <= tolerance) return;
    rotate(A, V, 0, 1, 2, tolerance);
    rotate(A, V, 0, 2, 1, tolerance);
    rotate(A, V, 1, 2, 0, tolerance);
  }
}

// A unit vector orthogonal to the unit vector u.
Eigen::Vector3d anyOrthogonal(const Eigen::Vector3d& u) {
  int axis = 0;
  u.cwiseAbs().minCoeff(&axis);
  return u.cross(Eigen::Vector3d::Unit(axis)).normalized();
}

}  // namespace

SignedSvd computeSignedSvd(const Eigen::Matrix3d& F) {
  // V from the eigenvectors of F^T F (sorted by decreasing eigenvalue, det V = +1), then U by
  // Gram-Schmidt on the (orthogonal) columns of F V with u2 = u0 x u1, so det U = +1 and the
  // smallest singular value s2 = u2 . F v2 carries the sign of det F.
  Eigen::Matrix3d A = F.transpose() * F;
  SignedSvd out;
  jacobiEigen(A, out.V);
  Eigen::Vector3d eigenvalues = A.diagonal();
  for (int i = 0; i < 2; ++i) {  // selection sort, decreasing
    int k = i;
    eigenvalues.tail(3 - i).maxCoeff(&k);
    k += i;
    if (k != i) {
      std::swap(eigenvalues(i), eigenvalues(k));
      out.V.col(i).swap(out.V.col(k));
    }
  }
  if (out.V.determinant() < 0.0) out.V.col(2) *= -1.0;

  const Eigen::Matrix3d B = F * out.V;
  const double b0 = B.col(0).norm();
  if (b0 == 0.0) {  // F = 0
    out.U.setIdentity();
    out.s.setZero();
    return out;
  }
  out.U.col(0) = B.col(0) / b0;
  Eigen::Vector3d u1 = B.col(1) - out.U.col(0).dot(B.col(1)) * out.U.col(0);
  const double n1 = u1.norm();
  out.U.col(1) = n1 > 1e-14 * b0 ? Eigen::Vector3d(u1 / n1) : anyOrthogonal(out.U.col(0));
  out.U.col(2) = out.U.col(0).cross(out.U.col(1));
  out.s << b0, out.U.col(1).dot(B.col(1)), out.U.col(2).dot(B.col(2));
  return out;
}

}  // namespace surgical_sim::core
