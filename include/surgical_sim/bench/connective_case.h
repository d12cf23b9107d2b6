#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/connective/rigid_node_implicit_euler.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

/// Skinning weights of a rigid-node beam.
enum class RigidNodeWeights {
  Trilinear,  ///< trilinearGridLayout: a rigid node per grid point, 27 samples per cell
  Tet,        ///< tetMeshLayout of makeBeam's Tet4 mesh (symmetric split), 4 samples per tet
};

/// "trilinear" or "tet".
const char* rigidNodeWeightsName(RigidNodeWeights weights);

/// A rectangular rigid-node beam along x (x in [0, size.x], y and z centred on 0) clamped at
/// x = 0 (every DOF of the rigid nodes there), loaded by its own weight.
struct RigidNodeBeamSpec {
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  ///< [m], each finite and > 0
  Material material = Material::create(1e4, 0.3, 1000.0);
  Eigen::Vector3d gravity = Eigen::Vector3d(0, 0, -9.81);  ///< [m/s^2]
  int component = 2;  ///< tip displacement component measured (0 x, 1 y, 2 z)
  /// Grid cells along x, y, z, each >= 1: (cells + 1) rigid nodes per axis for both weights.
  Eigen::Vector3i cells = Eigen::Vector3i::Ones();
  RigidNodeWeights weights = RigidNodeWeights::Trilinear;
  /// Quasi-static load increments (gravity k / load_steps, k = 1..load_steps), >= 0 (0: no
  /// quasi-static solve).
  int load_steps = 1;
  double relative_tolerance = 1e-8;  ///< of each Newton solve, in (0, 1)
  int max_iterations = 200;          ///< Newton iterations per load increment, >= 1
  /// Linearized implicit Euler steps timed from rest after one untimed step, >= 0 (0: none).
  int timed_steps = 0;
  double time_step = 0.01;    ///< [s], > 0
  double mass_damping = 1.0;  ///< Rayleigh alpha of the timed steps [1/s], >= 0
  /// Factor reuse of the timed steps (refresh_interval 1: a direct solve every step).
  core::RigidNodeImplicitEulerSettings integrator;
};

/// Measured outcome of runRigidNodeBeam.
struct RigidNodeBeamResult {
  int nodes = 0;
  int samples = 0;
  int dofs = 0;  ///< 6 per rigid node (fixed ones included)
  /// Quasi-static: mean displacement of the rigid nodes at x = size.x along `component` [m]
  /// (NaN without a quasi-static solve or when it failed; the last accepted iterate when an
  /// increment did not converge).
  double tip = std::numeric_limits<double>::quiet_NaN();
  double residual = 0.0;      ///< largest relative residual of the load increments [-]
  int newton_iterations = 0;  ///< summed over the load increments
  double solve_ms = 0.0;      ///< wall time of the quasi-static solve [ms]
  /// Mean wall and thread CPU time of one timed implicit Euler step [ms] (NaN: none timed).
  double ms_per_step = std::numeric_limits<double>::quiet_NaN();
  double cpu_ms_per_step = std::numeric_limits<double>::quiet_NaN();
  /// Mean wall time per timed step of the sample loop (forces and tangent) and of the
  /// factorization [ms].
  double forces_ms = std::numeric_limits<double>::quiet_NaN();
  double factor_ms = std::numeric_limits<double>::quiet_NaN();
  /// Mean wall time per timed step of the linear solve (triangular solves or conjugate
  /// gradients) [ms], mean linear iterations per timed step (1: direct), and factorizations over
  /// the timed steps.
  double linear_solve_ms = std::numeric_limits<double>::quiet_NaN();
  double linear_iterations = std::numeric_limits<double>::quiet_NaN();
  int factorizations = 0;
  /// First non-Ok status of the quasi-static solve and of the timed steps, or Ok.
  StepStatus status = StepStatus::Ok;
};

/// BENCHMARKS.md T1 with rigid nodes: the steel cantilever 16 x 0.5 x 0.5 m (E 200 GPa, nu 0.3,
/// 7800 kg/m^3) under self-weight along -y, trilinear weights, `nodes` rigid nodes per axis
/// (each >= 2), one load increment, Newton to 1e-8; its tip is the y displacement.
RigidNodeBeamSpec t1CantileverSpec(const Eigen::Vector3i& nodes);

/// Builds the beam of `spec` and runs its quasi-static solve and its timed steps.
/// @throws std::invalid_argument naming a field of spec out of range
RigidNodeBeamResult runRigidNodeBeam(const RigidNodeBeamSpec& spec);

/// Thread CPU time of the caller [s].
double threadCpuSeconds();

}  // namespace surgical_sim::bench
