#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Outcome of an MLS evaluation.
enum class MlsStatus {
  Ok,
  NonFinite,       ///< a non-finite input position
  TooFewPoints,    ///< fewer than 4 neighbours (a linear basis needs 4 non-coplanar points)
  IllConditioned,  ///< the scaled moment matrix is singular or its condition number > 1e10
};

/// "ok", "non_finite", "too_few_points", "ill_conditioned".
const char* toString(MlsStatus status);

/// Quartic spline kernel without its normalisation constant (which cancels in MLS):
/// w(s) = 1 - 6 s^2 + 8 s^3 - 3 s^4 for s = r / h in [0, 1], 0 beyond [-].
double quarticSplineKernel(double s);

/// Linear-basis MLS shape functions at one point and their gradients there.
struct MlsShapeFunctions {
  MlsStatus status = MlsStatus::Ok;
  Eigen::VectorXd phi;                            ///< phi_i(x) [-], size k (empty unless Ok)
  Eigen::Matrix<double, Eigen::Dynamic, 3> grad;  ///< d phi_i / dx [1/m], k x 3 (empty unless Ok)
  double condition = 0.0;  ///< condition number of the moment matrix in the scaled basis [-]
};

/// Moving-least-squares shape functions of the linear basis p = [1, x, y, z] with the quartic
/// spline kernel, evaluated at x: phi_i = p(x)^T A^-1 w_i p(x_i), A = sum_i w_i p(x_i) p(x_i)^T,
/// w_i = quarticSplineKernel(|x - x_i| / h) with a fixed support radius h. The basis is centred on
/// x and scaled by h (the same functions, better conditioned), so the result does not depend on
/// the length unit. Gradients (h held fixed) include the derivatives of the kernel and of A^-1.
/// The functions sum to 1 and reproduce linear fields and their gradients exactly.
/// Allocates (meant for precomputation). Never returns NaN: a degenerate neighbourhood gives a
/// status other than Ok and empty phi / grad.
/// @param x evaluation point [m].
/// @param points neighbour positions x_i [m], 3 x k; those farther than h get no weight.
/// @param support kernel support radius h [m], > 0.
MlsShapeFunctions computeMlsShapeFunctions(const Eigen::Vector3d& x, const Eigen::Matrix3Xd& points,
                                           double support);

/// As above with kernel distances r_i = |x - x_i| + detours(i): w_i = quarticSplineKernel(r_i / h).
/// A detour (e.g. the excess of a path along a topology graph over the straight distance) lowers
/// the weight of a particle seen around a cut. The kernel gradient uses the Euclidean direction,
/// dr_i/dx = (x - x_i) / |x - x_i| (0 at x = x_i when the detour is > 0), so the gradients are
/// the exact derivatives of the functions so defined. Zero detours give bit-identical results to
/// the overload above.
/// @param detours size k, each finite and >= 0 [m] (otherwise status NonFinite).
MlsShapeFunctions computeMlsShapeFunctions(const Eigen::Vector3d& x, const Eigen::Matrix3Xd& points,
                                           double support, const Eigen::VectorXd& detours);

}  // namespace surgical_sim::core
