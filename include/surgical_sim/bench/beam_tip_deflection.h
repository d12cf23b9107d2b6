#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "surgical_sim/core/solve/dynamics_problem.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

/// Dirichlet conditions holding `nodes` (each in [0, n)) at their positions in x (size 3n) [m].
DirichletBc clampNodes(const std::vector<int>& nodes, const Eigen::VectorXd& x);

/// Static tip deflection of a (possibly cut) cantilever along x (T3 in BENCHMARKS.md): nodes at
/// rest x <= 1e-9 length are clamped, a uniform body acceleration `load` [m/s^2] acts on the
/// model's masses (bodyForce). The static equilibrium is found by an overdamped relaxation
/// (linearized implicit Euler, CHOLMOD, dt = 1 s, mass damping 1e3 1/s) until the tip moves less
/// than 1e-9 of its deflection in a step: unlike a pure quasi-static solve, this tolerates the
/// virtual nodes of a cut, which may hang on a single real node (a mechanism of K alone).
/// length = largest rest x.
/// @return mean displacement along load of the nodes at the free end (rest x >= length
///         (1 - 1e-9)) [m], or NaN if a step fails or 500 steps do not converge.
double beamTipDeflection(const TissueModel& model, const Eigen::Vector3d& load);

/// As above with the clamped nodes and the measured points given (e.g. a meshless model measured
/// at mesh nodes through its interpolation): `clamped` nodes keep their rest positions, `tip`
/// (points x nodes, e.g. EfgModel::interpolation) maps node positions to the measured points.
/// @return mean displacement of the points along load [m], or NaN as above.
double beamTipDeflection(const TissueModel& model, const Eigen::Vector3d& load,
                         const std::vector<int>& clamped, const Eigen::SparseMatrix<double>& tip);

}  // namespace surgical_sim::bench
