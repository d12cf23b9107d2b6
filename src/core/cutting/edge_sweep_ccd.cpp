#include "surgical_sim/core/cutting/edge_sweep_ccd.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

#include "surgical_sim/core/contact/closest_points_segment_segment.h"

namespace surgical_sim::core {

namespace {

double evalCubic(const Eigen::Vector4d& c, double t) {
  return c[0] + t * (c[1] + t * (c[2] + t * c[3]));
}

/// Root of the cubic on [lo, hi] where it changes sign (monotone piece), by bisection.
double bisect(const Eigen::Vector4d& c, double lo, double hi) {
  double f_lo = evalCubic(c, lo);
  for (int i = 0; i < 60 && hi - lo > 1e-14; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double f_mid = evalCubic(c, mid);
    if ((f_mid < 0.0) == (f_lo < 0.0)) {
      lo = mid;
      f_lo = f_mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace

Eigen::Vector4d coplanarityCubic(const Eigen::Vector3d& b0_start, const Eigen::Vector3d& b1_start,
                                 const Eigen::Vector3d& b0_end, const Eigen::Vector3d& b1_end,
                                 const Eigen::Vector3d& e0_start, const Eigen::Vector3d& e1_start,
                                 const Eigen::Vector3d& e0_end, const Eigen::Vector3d& e1_end) {
  // u(t) = b1 - b0, v(t) = e0 - b0, w(t) = e1 - b0, each linear: value at 0 plus t times rate.
  const Eigen::Vector3d u0 = b1_start - b0_start;
  const Eigen::Vector3d v0 = e0_start - b0_start;
  const Eigen::Vector3d w0 = e1_start - b0_start;
  const Eigen::Vector3d u1 = (b1_end - b0_end) - u0;
  const Eigen::Vector3d v1 = (e0_end - b0_end) - v0;
  const Eigen::Vector3d w1 = (e1_end - b0_end) - w0;
  const Eigen::Vector3d uv0 = u0.cross(v0);
  const Eigen::Vector3d uv1 = u1.cross(v0) + u0.cross(v1);
  const Eigen::Vector3d uv2 = u1.cross(v1);
  return {uv0.dot(w0), uv1.dot(w0) + uv0.dot(w1), uv2.dot(w0) + uv1.dot(w1), uv2.dot(w1)};
}

std::optional<EdgeSweepHit> edgeSweepCrossing(
    const Eigen::Vector3d& b0_start, const Eigen::Vector3d& b1_start, const Eigen::Vector3d& b0_end,
    const Eigen::Vector3d& b1_end, const Eigen::Vector3d& e0_start, const Eigen::Vector3d& e1_start,
    const Eigen::Vector3d& e0_end, const Eigen::Vector3d& e1_end, double tolerance) {
  const Eigen::Vector4d c =
      coplanarityCubic(b0_start, b1_start, b0_end, b1_end, e0_start, e1_start, e0_end, e1_end);
  // Length scale of the configuration, for the "f is zero" test [m].
  const double scale = std::max({(b1_start - b0_start).norm(), (e1_start - e0_start).norm(),
                                 (b0_start - e0_start).norm(), (b0_end - b0_start).norm(),
                                 (e0_end - e0_start).norm(), tolerance});
  const double f_zero = 1e-12 * scale * scale * scale;

  std::array<double, 16> candidates{};
  int n = 0;
  if (c.cwiseAbs().maxCoeff() <= f_zero) {
    for (int i = 0; i <= 8; ++i) candidates[n++] = i / 8.0;
  } else {
    // Break points: 0, the roots of f' = c1 + 2 c2 t + 3 c3 t^2 inside (0, 1), 1.
    std::array<double, 4> breaks{};
    int nb = 0;
    breaks[nb++] = 0.0;
    const double qa = 3.0 * c[3], qb = 2.0 * c[2], qc = c[1];
    std::array<double, 2> crit{};
    int nc = 0;
    if (std::abs(qa) > 1e-300) {
      const double disc = qb * qb - 4.0 * qa * qc;
      if (disc >= 0.0) {
        const double sq = std::sqrt(disc);
        // Numerically stable pair of roots.
        const double q = -0.5 * (qb + (qb >= 0.0 ? sq : -sq));
        crit[nc++] = q / qa;
        if (q != 0.0) crit[nc++] = qc / q;
      }
    } else if (std::abs(qb) > 1e-300) {
      crit[nc++] = -qc / qb;
    }
    std::sort(crit.begin(), crit.begin() + nc);
    for (int i = 0; i < nc; ++i)
      if (crit[i] > 0.0 && crit[i] < 1.0) breaks[nb++] = crit[i];
    breaks[nb++] = 1.0;
    for (int i = 0; i < nb; ++i) {
      if (std::abs(evalCubic(c, breaks[i])) <= f_zero) candidates[n++] = breaks[i];
      if (i + 1 < nb) {
        const double fa = evalCubic(c, breaks[i]), fb = evalCubic(c, breaks[i + 1]);
        if ((fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0))
          candidates[n++] = bisect(c, breaks[i], breaks[i + 1]);
      }
    }
    std::sort(candidates.begin(), candidates.begin() + n);
  }
  for (int i = 0; i < n; ++i) {
    const double t = candidates[i];
    const SegmentSegmentClosest cp = closestPointsSegmentSegment(
        b0_start + t * (b0_end - b0_start), b1_start + t * (b1_end - b1_start),
        e0_start + t * (e0_end - e0_start), e1_start + t * (e1_end - e1_start));
    if (cp.distance_squared <= tolerance * tolerance) return EdgeSweepHit{t, cp.t, cp.s};
  }
  return std::nullopt;
}

}  // namespace surgical_sim::core
