#pragma once

#include <Eigen/Core>
#include <functional>
#include <utility>

#include "surgical_sim/core/robot/box_qp_solver.h"
#include "surgical_sim/core/robot/continuum_robot_model.h"

namespace surgical_sim::core {

/// Outcome of an inverse solve.
enum class InverseStatus {
  Converged,      ///< effector error <= tolerance
  Unreachable,    ///< the actuation stopped changing above tolerance: closest feasible actuation
  MaxIterations,  ///< iteration cap reached while still improving (or the model did not converge)
  InvalidTarget,  ///< target not finite or farther than max_target_distance from the base
  Interrupted,    ///< the cancel check (setCancelCheck) asked to stop between two iterations
};

/// Lower-case name, e.g. "unreachable".
const char* toString(InverseStatus status);

/// Settings of InverseController (numerical choices, documented defaults).
struct InverseControllerSettings {
  ModelSolveSettings model;    ///< equilibrium solve after each QP
  int qp_max_iterations = 50;  ///< active-set iterations per QP [-], >= 1
  /// epsilon of the energy regularization, relative: eps = regularization tr(W_ea^T W_ea) /
  /// tr(W_aa) [-], in [0, 1).
  double regularization = 1e-6;
  /// targets farther than this from the robot_base origin are InvalidTarget [m], > 0.
  double max_target_distance = 10.0;
  /// Unreachable when an iteration changes the scaled actuation by less than this and improves
  /// the error by less than the tolerance [-], in (0, 1).
  double stall_tolerance = 1e-6;
};

/// @throws std::invalid_argument naming "inverse_controller.<field>" with unit and range.
void validateInverseControllerSettings(const InverseControllerSettings& settings);

/// Result of an inverse solve. message is a static string (no allocation).
struct InverseResult {
  Eigen::VectorXd actuation;    ///< per actuator [Pa] / [N]
  double effector_error = 0.0;  ///< |p_tip - p_target| of the model [m]
  int iterations = 0;           ///< model-update + QP iterations
  int qp_iterations = 0;        ///< summed active-set iterations
  InverseStatus status = InverseStatus::MaxIterations;
  const char* message = "";
};

/// Quasi-static inverse control of a ContinuumRobotModel (Bosman §5.3 with the digest's loop):
/// per iteration, at the current equilibrium: K (block-tridiagonal), W_ea = J_e K^-1 J_a^T
/// (3 x m, tip position rows), W_aa = J_a K^-1 J_a^T, free gap delta_e = e - W_ea lambda; box QP
/// min 1/2 l^T (W_ea^T W_ea + eps W_aa + mu I) l + l^T W_ea^T delta_e within the actuator bounds
/// (mu = 1e-9 tr(H) / m breaks ties between antagonistic actuations); then the
/// model equilibrium under the new actuation. Buffers sized in the constructor; iterations
/// allocate nothing.
class InverseController {
 public:
  /// @param model robot model, not owned, outlives the controller; its state is the controller's.
  /// @throws std::invalid_argument from validateInverseControllerSettings.
  InverseController(ContinuumRobotModel& model, const InverseControllerSettings& settings);

  /// Iterates model update + QP until |e| <= tolerance [m] or max_iterations; writes into result
  /// (its actuation must already have numActuators() entries to avoid allocating).
  void solveTarget(const Eigen::Vector3d& p_target, double tolerance, int max_iterations,
                   InverseResult& result);
  /// Convenience overload returning by value.
  InverseResult solveTarget(const Eigen::Vector3d& p_target, double tolerance, int max_iterations);
  /// One control step (one model update + QP) toward p_target, for path following.
  InverseResult step(const Eigen::Vector3d& p_target);

  /// Current actuation [Pa] / [N].
  const Eigen::VectorXd& actuation() const { return lambda_; }
  /// Zero actuation (clamped to the bounds) and rest shape.
  void reset();
  /// `cancelled` is called before every iteration of solveTarget (from its thread); when it
  /// returns true the solve stops with status Interrupted, keeping the last iterate. Empty: never
  /// cancelled. Lets another thread interrupt a long solve (e.g. a reset or a shutdown).
  void setCancelCheck(std::function<bool()> cancelled) { cancelled_ = std::move(cancelled); }

 private:
  /// One iteration; returns false if the model could not be factorized or solved.
  bool iterate(const Eigen::Vector3d& p_target, int* qp_iterations);

  ContinuumRobotModel& model_;
  InverseControllerSettings settings_;
  std::function<bool()> cancelled_;
  BoxQpSolver qp_;
  Eigen::VectorXd lambda_, lambda_new_, lambda_prev_, lo_, hi_, c_, delta_;
  Eigen::MatrixXd Ja_, X_, Wea_, Waa_, H_;
};

}  // namespace surgical_sim::core
