#pragma once

#include <Eigen/Core>
#include <string>

#include "surgical_sim/core/cutting/tet_cutter.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {

/// Static tip deflection of a (possibly cut) cantilever along x (T3 in BENCHMARKS.md): nodes at
/// rest x <= 1e-9 length are clamped, a uniform body acceleration `load` [m/s^2] acts on the
/// cutter's masses, and the quasi-static Newton integrator with CHOLMOD finds the equilibrium.
/// @param model_name tissue model (makeTissueModel()).
/// @return mean displacement along load of the nodes at the free end (rest x >= length - 1e-9
///         length) [m], or NaN if the solve fails.
double cutBeamTipDeflection(const TetCutter& cutter, const std::string& model_name,
                            const Material& material, const Eigen::Vector3d& load);

}  // namespace surgical_sim::core
