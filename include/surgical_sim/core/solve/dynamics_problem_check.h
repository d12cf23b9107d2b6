#pragma once

#include "surgical_sim/core/solve/dynamics_problem.h"

namespace surgical_sim::core {

/// Consistency of a problem with a state: model set; x, v, external_force of size 3n (n nodes of
/// the model) and finite; damping coefficients finite and >= 0; Dirichlet DOFs in [0, 3n) with
/// one finite prescribed position each. Returns nullptr if consistent, otherwise a static
/// description naming the field (no allocation: usable inside step()).
const char* findProblemError(const DynamicsProblem& problem, const SimulationState& state);

/// Configuration-time form of findProblemError.
/// @throws std::invalid_argument naming the inconsistent field.
void validateDynamicsProblem(const DynamicsProblem& problem, const SimulationState& state);

}  // namespace surgical_sim::core
