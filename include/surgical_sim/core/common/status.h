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
  /// A blade sweep was not applied because the cut would pass a limit (the meshless cut
  /// surface's triangle budget): nothing was cut along it, and the state, model and surface are
  /// consistent and as before the sweep.
  CutRefused,
};

/// Lower-case name of a status, e.g. "not_converged".
const char* toString(StepStatus status);

/// Wall time (steady_clock) of the phases of one integrator step [s], each summed over every
/// occurrence in the step (a Newton step assembles and solves once per iteration). The phases
/// do not overlap, so their sum is at most the step's wall time; the rest (residual norms,
/// energies, line search, copies) is not attributed. Explicit schemes leave them 0.
struct StepPhaseTimes {
  /// Element forces and tangents scattered into the global force and stiffness (the tissue
  /// model's addInternalForceAndStiffness / assembleStiffness; a Newton scheme's residual
  /// evaluations, addInternalForce and a few vector operations, count here too).
  double forces = 0.0;
  /// System matrix A from the mass, damping and stiffness, with its Dirichlet projection.
  double assembly = 0.0;
  /// LinearSolver::factorize: numeric factorization or preconditioner set-up.
  double factorization = 0.0;
  /// LinearSolver::solve: triangular solves or the iterations of an iterative solver.
  double linear_solve = 0.0;
  /// Sum of the four phases [s].
  double sum() const { return forces + assembly + factorization + linear_solve; }
};

/// Per-step diagnostics returned by every integrator.
struct StepReport {
  StepStatus status = StepStatus::Ok;
  int newton_iterations = 0;  ///< nonlinear iterations taken (0 for explicit schemes)
  int linear_iterations = 0;  ///< summed linear-solver iterations (1 per direct solve)
  /// Relative residual of the step's solve [-], normalised so that the solve converged exactly
  /// when residual <= its relative tolerance. Newton schemes (implicit_euler_newton,
  /// quasi_static): |r| / max(|r_0|, round-off floor of r / tolerance) (NewtonIntegratorBase), so
  /// an Ok step reports <= integrator.relative_tolerance (a step converged by round-off included)
  /// and a NotConverged one more; quasi_static: the largest over its load increments.
  /// implicit_euler_linearized: |b - A x| / |b| of its linear solve (<= the solver's tolerance
  /// when that solve converged). symplectic_euler: 0 (no solve).
  double residual = 0.0;
  double energy = 0.0;    ///< kinetic + elastic - external work potential after the step [J]
  StepPhaseTimes phases;  ///< where the step's time went (implicit schemes)
};

}  // namespace surgical_sim::core
