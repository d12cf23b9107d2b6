#pragma once

#include <string>

namespace surgical_sim::core {

/// Outcome of one simulation step or solve. The step path never throws; it returns one of these.
enum class StepStatus {
  Ok,            ///< converged / finished normally
  NotConverged,  ///< iteration limit reached; state is finite and usable but above tolerance
  SolverFailed,  ///< the linear solver failed (e.g. matrix not positive definite)
  NonFinite,     ///< NaN or Inf detected; the state was restored to the last finite one
  BlowUp,        ///< explicit integration became unstable (energy or velocity grew without bound)
  /// A tool's contact or grasp force reached its limit (ToolSpec::max_force): the force was
  /// capped (a grasp slipped); the state is finite and bounded but the tool pose is not honoured.
  ContactLimited,
};

/// Lower-case name of a status, e.g. "not_converged".
const char* toString(StepStatus status);

/// Per-step diagnostics returned by every integrator.
struct StepReport {
  StepStatus status = StepStatus::Ok;
  int newton_iterations = 0;  ///< nonlinear iterations taken (0 for explicit schemes)
  int linear_iterations = 0;  ///< summed linear-solver iterations (1 per direct solve)
  double residual = 0.0;      ///< final relative residual of the nonlinear problem [-]
  double energy = 0.0;        ///< kinetic + elastic - external work potential after the step [J]
};

}  // namespace surgical_sim::core
