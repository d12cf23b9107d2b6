#include "surgical_sim/core/tissue/efg_shape_functions.h"

#include <Eigen/Dense>
#include <cmath>

namespace surgical_sim::core {
namespace {

// Largest accepted condition number of the scaled moment matrix [-].
constexpr double kMaxCondition = 1e10;

}  // namespace

const char* toString(MlsStatus status) {
  switch (status) {
    case MlsStatus::Ok:
      return "ok";
    case MlsStatus::NonFinite:
      return "non_finite";
    case MlsStatus::TooFewPoints:
      return "too_few_points";
    case MlsStatus::IllConditioned:
      return "ill_conditioned";
  }
  return "?";
}

double quarticSplineKernel(double s) {
  if (s >= 1.0) return 0.0;
  const double s2 = s * s;
  return 1.0 - 6.0 * s2 + 8.0 * s2 * s - 3.0 * s2 * s2;
}

MlsShapeFunctions computeMlsShapeFunctions(const Eigen::Vector3d& x, const Eigen::Matrix3Xd& points,
                                           double support) {
  return computeMlsShapeFunctions(x, points, support, Eigen::VectorXd::Zero(points.cols()));
}

MlsShapeFunctions computeMlsShapeFunctions(const Eigen::Vector3d& x, const Eigen::Matrix3Xd& points,
                                           double support, const Eigen::VectorXd& detours) {
  MlsShapeFunctions out;
  const Eigen::Index k = points.cols();
  if (!x.allFinite() || !points.allFinite() || !std::isfinite(support) || detours.size() != k ||
      !detours.allFinite() || (detours.array() < 0.0).any()) {
    out.status = MlsStatus::NonFinite;
    return out;
  }
  if (k < 4) {
    out.status = MlsStatus::TooFewPoints;
    return out;
  }
  const Eigen::Matrix3Xd d = points.colwise() - x;  // x_i - x [m]
  if (!(support > 0.0)) {
    out.status = MlsStatus::IllConditioned;
    return out;
  }
  const double h = support;
  // Scaled basis p_i = [1, (x_i - x) / h]; at x, p = e0 and dp/dx_k = e_(k+1) / h.
  Eigen::Matrix<double, 4, Eigen::Dynamic> p(4, k);
  p.row(0).setOnes();
  p.bottomRows<3>() = d / h;
  Eigen::VectorXd w(k);
  Eigen::Matrix<double, Eigen::Dynamic, 3> dw(k, 3);  // d w_i / dx [1/m]
  for (Eigen::Index i = 0; i < k; ++i) {
    const double r = d.col(i).norm();  // Euclidean distance [m]
    const double s = (r + detours(i)) / h;
    w(i) = quarticSplineKernel(s);
    // dw/dr = -12 s (1 - s)^2 / h and dr/dx = (x - x_i) / r = -d_i / r: dw/dx = 12 s (1 - s)^2
    // d_i / (h r), which is 12 (1 - s)^2 d_i / h^2 without a detour.
    double dw_dr_over_r = 0.0;
    if (s < 1.0 && detours(i) == 0.0) {
      dw_dr_over_r = 12.0 * (1.0 - s) * (1.0 - s) / (h * h);
    } else if (s < 1.0 && r > 0.0) {
      dw_dr_over_r = 12.0 * s * (1.0 - s) * (1.0 - s) / (h * r);
    }
    dw.row(i) = dw_dr_over_r * d.col(i).transpose();
  }
  const Eigen::Matrix4d A = p * w.asDiagonal() * p.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(A, Eigen::EigenvaluesOnly);
  const double lo = eig.eigenvalues().minCoeff();
  const double hi = eig.eigenvalues().maxCoeff();
  out.condition = lo > 0.0 ? hi / lo : INFINITY;
  if (!(lo > 0.0) || out.condition > kMaxCondition) {
    out.status = MlsStatus::IllConditioned;
    return out;
  }
  const Eigen::LDLT<Eigen::Matrix4d> A_inv(A);
  const Eigen::Vector4d gamma = A_inv.solve(Eigen::Vector4d::UnitX());
  out.phi = (w.asDiagonal() * p.transpose() * gamma);
  out.grad.resize(k, 3);
  const Eigen::VectorXd p_gamma = p.transpose() * gamma;  // p_i . gamma
  for (int c = 0; c < 3; ++c) {
    // d gamma / dx_c = A^-1 (dp/dx_c - dA/dx_c gamma), dA/dx_c = sum_i dw_i/dx_c p_i p_i^T.
    const Eigen::Vector4d dA_gamma = p * (dw.col(c).cwiseProduct(p_gamma));
    const Eigen::Vector4d dgamma = A_inv.solve(Eigen::Vector4d::Unit(c + 1) / h - dA_gamma);
    out.grad.col(c) = dw.col(c).cwiseProduct(p_gamma) + w.cwiseProduct(p.transpose() * dgamma);
  }
  return out;
}

}  // namespace surgical_sim::core
