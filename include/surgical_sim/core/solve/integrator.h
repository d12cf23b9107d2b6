#pragma once

#include <string>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/solve/dynamics_problem.h"

namespace surgical_sim::core {

/// Advances a DynamicsProblem by one time step. The integrator keeps its own preallocated work
/// buffers (sized on first use / when the model size changes) and its linear solver.
/// step() never throws and never leaves NaN/Inf in the state: on failure it restores the state
/// from before the step and returns a non-Ok status.
class Integrator {
 public:
  virtual ~Integrator() = default;
  /// "symplectic_euler", "implicit_euler_linearized", "implicit_euler_newton", "quasi_static".
  virtual std::string name() const = 0;
  /// Advance by dt [s] (quasi-static ignores dt except for load stepping and sets v = 0).
  virtual StepReport step(const DynamicsProblem& problem, double dt, SimulationState& state) = 0;
  /// Forget cached factorizations / patterns (call after a topology change).
  virtual void reset() = 0;
};

}  // namespace surgical_sim::core
