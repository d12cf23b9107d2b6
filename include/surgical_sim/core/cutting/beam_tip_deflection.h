#pragma once

#include <Eigen/Core>

#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// Static tip deflection of a (possibly cut) cantilever along x (T3 in BENCHMARKS.md): nodes at
/// rest x <= 1e-9 length are clamped, a uniform body acceleration `load` [m/s^2] acts on the
/// model's masses (bodyForce), and the quasi-static Newton integrator with CHOLMOD (relative
/// tolerance 1e-10) finds the equilibrium. length = largest rest x.
/// @return mean displacement along load of the nodes at the free end (rest x >= length
///         (1 - 1e-9)) [m], or NaN if the solve fails.
double beamTipDeflection(const TissueModel& model, const Eigen::Vector3d& load);

}  // namespace surgical_sim::core
