#include "surgical_sim/core/tissue/signed_svd.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <utility>

#include "surgical_sim/core/tissue/cofactor.h"

namespace surgical_sim::core {
namespace {

constexpr int kMaxSweeps = 12;
constexpr double kOffDiagonalTolerance = 1e-15;  // relative to the largest diagonal entry

// det F / (||F||_F^2 / 3)^(3/2) (1 for a rotation, 0 for a singular F) above which the Newton
// polar iteration is used: singular values within a factor ~20 of each other.
constexpr double kMinPolarConditioning = 0.1;
constexpr int kMaxPolarIterations = 12;
// Squared Frobenius change of a Newton polar iterate below which the iterate is converged: the
// error of the new iterate is about half the square of the change, 5e-17.
constexpr double kPolarStepTolerance = 1e-16;

// Symmetric 3 x 3 matrix held in scalars: diagonal d and off-diagonal o, o[r] = A(p, q) for
// {p, q, r} = {0, 1, 2}.
struct Symmetric3 {
  double d[3];
  double o[3];
};

// One Jacobi rotation in the (P, Q) plane annihilating A(P, Q) (R the third index), accumulated
// into the columns of V. With h = A(Q, Q) - A(P, P) and r = sqrt(h^2 + 4 A(P, Q)^2), the rotation
// of angle <= pi/4 has tan = 2 A(P, Q) sgn(h) / (|h| + r) and moves the diagonal to the eigenvalues
// of the 2 x 2 block, (A(P, P) + A(Q, Q) -+ sgn(h) r) / 2. Compile-time indices keep A and V in
// registers.
template <int P, int Q, int R>
void rotate(Symmetric3& A, Eigen::Matrix3d& V, double tolerance) {
  const double apq = A.o[R];
  if (std::abs(apq) <= tolerance) return;
  const double h = A.d[Q] - A.d[P];
  const double r = std::sqrt(h * h + 4.0 * apq * apq);
  const double denominator = std::abs(h) + r;
  // (|h| + r)^2 + 4 apq^2 = 2 r (|h| + r)
  const double inverse_hypot = 1.0 / std::sqrt(2.0 * r * denominator);
  const double c = denominator * inverse_hypot;
  const double s = (h >= 0.0 ? 2.0 : -2.0) * apq * inverse_hypot;
  const double mean = 0.5 * (A.d[P] + A.d[Q]);
  const double half_split = h >= 0.0 ? 0.5 * r : -0.5 * r;
  A.d[P] = mean - half_split;
  A.d[Q] = mean + half_split;
  A.o[R] = 0.0;
  const double arp = A.o[Q];
  const double arq = A.o[P];
  A.o[Q] = c * arp - s * arq;
  A.o[P] = s * arp + c * arq;
  const Eigen::Vector3d vp = V.col(P);
  V.col(P) = c * vp - s * V.col(Q);
  V.col(Q) = s * vp + c * V.col(Q);
}

// Cyclic Jacobi eigen-decomposition of the symmetric A: on return A is diagonal and V (a product
// of plane rotations, det V = +1) holds the eigenvectors.
void jacobiEigen(Symmetric3& A, Eigen::Matrix3d& V) {
  V.setIdentity();
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    const double off = std::max({std::abs(A.o[0]), std::abs(A.o[1]), std::abs(A.o[2])});
    const double tolerance =
        kOffDiagonalTolerance * std::max({std::abs(A.d[0]), std::abs(A.d[1]), std::abs(A.d[2])});
    if (off <= tolerance) return;
    rotate<0, 1, 2>(A, V, tolerance);
    rotate<0, 2, 1>(A, V, tolerance);
    rotate<1, 2, 0>(A, V, tolerance);
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
  const Eigen::Matrix3d FtF = F.transpose() * F;
  Symmetric3 A{{FtF(0, 0), FtF(1, 1), FtF(2, 2)}, {FtF(1, 2), FtF(0, 2), FtF(0, 1)}};
  SignedSvd out;
  jacobiEigen(A, out.V);
  // Sorting network, decreasing; an odd number of swaps is undone in det V by negating v2.
  bool odd_swaps = false;
  const auto order = [&](int i, int j) {
    if (A.d[j] > A.d[i]) {
      std::swap(A.d[i], A.d[j]);
      out.V.col(i).swap(out.V.col(j));
      odd_swaps = !odd_swaps;
    }
  };
  order(0, 1);
  order(0, 2);
  order(1, 2);
  if (odd_swaps) out.V.col(2) *= -1.0;

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

Eigen::Matrix3d computeSignedRotation(const Eigen::Matrix3d& F) {
  // Newton's polar iteration X <- (X + X^-T) / 2 maps every singular value s to (s + 1/s) / 2 and
  // keeps the singular vectors, so from X0 = F / rms(s) it converges quadratically to U V^T when
  // det F > 0. Inverted, singular or badly conditioned F go through the signed SVD.
  const double det = F.determinant();
  const double mean_square = F.squaredNorm() / 3.0;  // mean of s_i^2
  if (det > 0.0 && det * det > kMinPolarConditioning * kMinPolarConditioning * mean_square *
                                   mean_square * mean_square) {
    Eigen::Matrix3d X = F / std::sqrt(mean_square);
    for (int k = 0; k < kMaxPolarIterations; ++k) {
      const Eigen::Matrix3d C = cofactor(X);  // det(X) X^-T
      const Eigen::Matrix3d next = 0.5 * (X + C / X.col(0).dot(C.col(0)));
      const double step = (next - X).squaredNorm();
      X = next;
      if (step < kPolarStepTolerance) return X;
    }
  }
  const SignedSvd svd = computeSignedSvd(F);
  return svd.U * svd.V.transpose();
}

}  // namespace surgical_sim::core
