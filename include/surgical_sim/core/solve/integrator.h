#pragma once

#include <Eigen/Core>
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
  /// The model was changed in place with its DOFs kept (a cut that re-selects neighbourhoods, new
  /// masses): the next step forgets every cached evaluation of the model and the compliance, and
  /// adopts the stiffness pattern if it changed. Unlike reset(), the linear solver keeps what stays
  /// valid (a factor-reusing preconditioner its factor, LinearSolver::analyzePattern) and the work
  /// buffers and an iterative solver's initial guess stay. Default: reset().
  virtual void modelChanged() { reset(); }
  /// Step compliance: after a successful step(), dx = d(x_{n+1}) / d(f_ext) f, the position
  /// response of the last step to an extra constant nodal force f added to f_ext [m per N].
  /// Exact forms: symplectic Euler dt^2 M^-1 f; linearized implicit Euler dt^2 A^-1 f with
  /// A = M + dt C + dt^2 K(x_n) the step's system matrix; Newton implicit Euler dt^2 A^-1 f with A
  /// at the last iterate; quasi-static K^-1 f with the tangent at the equilibrium found.
  /// Dirichlet DOFs of the last step get 0. This is the operator S of the contact
  /// (free-motion / correction) loop: W = H S H^T.
  /// @param f extra nodal force [N], size 3n, in the tissue frame
  /// @param dx position response [m], resized to 3n (allocation-free once it has that size). On
  ///        entry, if of size 3n and finite, the start of an iterative linear solver (a warm
  ///        start, e.g. the response to a nearby f); any other dx starts from zero. The answer
  ///        meets the solver's tolerance from any start; direct solvers ignore it.
  /// @return false (dx then unspecified) if unavailable: no usable step since construction or
  ///         reset(), a failed last step, a size mismatch, or a failed solve. Never throws.
  virtual bool applyStepCompliance(const Eigen::VectorXd& f, Eigen::VectorXd& dx) = 0;

  /// Running totals of applyStepCompliance since construction (never reset): a caller times the
  /// compliance solves of a phase (e.g. a contact solve) by the difference of two readings.
  struct ComplianceUse {
    double seconds = 0.0;  ///< wall time inside applyStepCompliance [s]
    long calls = 0;        ///< number of calls
    long iterations = 0;   ///< linear-solver iterations of their solves (1 per direct solve)
  };
  /// Zero for schemes whose compliance costs no solve (symplectic Euler: dt^2 M^-1 f).
  virtual ComplianceUse complianceUse() const { return {}; }
};

}  // namespace surgical_sim::core
