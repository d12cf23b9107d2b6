#pragma once
// A straight blade sweep shared by the scene cutting tests.

#include "surgical_sim/core/cutting/blade_sweep.h"

namespace surgical_sim::test {

/// A 20 cm blade along y (y in [-0.1, 0.1]) at x = x_cut moving down from z_from to z_to [m].
inline core::BladeSweep bladeDown(double x_cut, double z_from, double z_to) {
  const Eigen::Vector3d half_span(0.0, 0.1, 0.0);
  const Eigen::Vector3d top(x_cut, 0.0, z_from), bottom(x_cut, 0.0, z_to);
  core::BladeSweep sweep;
  sweep.start = (Eigen::Matrix<double, 3, 2>() << top - half_span, top + half_span).finished();
  sweep.end = (Eigen::Matrix<double, 3, 2>() << bottom - half_span, bottom + half_span).finished();
  return sweep;
}

}  // namespace surgical_sim::test
