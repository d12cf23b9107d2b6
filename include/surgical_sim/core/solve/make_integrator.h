#pragma once

#include <memory>
#include <string>

#include "surgical_sim/core/solve/integrator.h"
#include "surgical_sim/core/solve/integrator_settings.h"
#include "surgical_sim/core/solve/linear_solver.h"

namespace surgical_sim::core {

/// Creates an integrator by name: "symplectic_euler" (SymplecticEuler; linear_solver unused, may
/// be null), "implicit_euler_linearized", "implicit_euler_newton", "quasi_static" (these take
/// ownership of linear_solver, which must not be null).
/// @throws std::invalid_argument naming "integrator.type" for an unknown name, the offending
///         "integrator.*" setting (validateIntegratorSettings), or "solver" for a missing solver.
std::unique_ptr<Integrator> makeIntegrator(const std::string& name,
                                           const IntegratorSettings& settings,
                                           std::unique_ptr<LinearSolver> linear_solver);

}  // namespace surgical_sim::core
