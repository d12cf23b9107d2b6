#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/connective/connective_coupling.h"
#include "surgical_sim/core/solve/cholmod_solver.h"

namespace surgical_sim::core {

/// Settings of CoupledSolver.
struct CoupledSolverSettings {
  double mass_damping = 0.0;         ///< Rayleigh alpha [1/s], >= 0 (implicit Euler)
  double stiffness_damping = 0.0;    ///< Rayleigh beta [s], >= 0 (implicit Euler)
  int max_iterations = 50;           ///< Newton iterations, >= 1 (quasi-static)
  double relative_tolerance = 1e-9;  ///< |f~| <= tol forceScale(), in (0, 1) (quasi-static)
  int max_halvings = 30;             ///< line-search halvings, >= 0 (quasi-static)
};

/// Solvers of a ConnectiveCoupling: one sparse SPD system A = c_M M~ + c_K K~ (symmetrized,
/// the organs' tangents projected to SPD) over the free organ nodes and free rigid nodes,
/// factorized by CHOLMOD with its symbolic analysis done once. Without mass (quasi-static), or
/// if A does not factorize, the free rigid-node rotation diagonal is shifted by
/// kRotationShifts[k] times its mean, the smallest that factorizes (the drilling modes of
/// RigidNodeTangentSystem). If no shift factorizes (large grasp or contact forces make the
/// mapping and geometric terms strongly indefinite), K~ is rebuilt without them
/// (CouplingTangentOptions::geometric off) and the shifts tried again. Shifts and the dropped
/// terms change increments, never residuals.
class CoupledSolver {
 public:
  /// @throws std::invalid_argument naming a setting out of range
  explicit CoupledSolver(ConnectiveCoupling& coupling, const CoupledSolverSettings& settings = {});

  /// Linearized implicit Euler step of dt [s] (finite, > 0):
  ///   (M~ + h D + h^2 K~) du = h (f~ - D u - h K~ u),   D = alpha M~ + beta K~,
  ///   u += du, free organ nodes x += h u, rigid nodes q <- q (+) h u, attached nodes mapped.
  /// Ok; SolverFailed / NonFinite with the state restored. report.energy: kinetic (step's mass)
  /// + potential after the step [J]; report.phases: where the time went.
  /// @throws std::invalid_argument for a bad dt, state or loads
  StepReport step(const CoupledLoads& loads, double dt, CoupledState& state);

  /// Quasi-static equilibrium f~ = 0 by Newton's method with an Armijo line search on the
  /// potential Pi. Ok when converged; NotConverged (last accepted iterate kept) at the iteration
  /// cap or when the line search finds no decrease; SolverFailed / NonFinite with the state
  /// restored. Velocities are left zero. report.residual: |f~| / forceScale() at the end.
  StepReport solveStatic(const CoupledLoads& loads, CoupledState& state);

  /// Whether the last factorization dropped the geometric terms.
  bool usedMaterialTangentOnly() const { return material_only_; }

 private:
  /// factorize() the full tangent that coupling_ holds (assembled at state, loads); if that
  /// fails, reassemble it without the geometric terms (with mass if mass_coefficient != 0;
  /// the force is unchanged) and factorize again. Time added to phases.
  bool factorizeAssembled(const CoupledState& state, const CoupledLoads& loads,
                          double mass_coefficient, double stiffness_coefficient,
                          StepPhaseTimes& phases);
  /// system_ = c_M M~ + c_K K~ factorized (with the smallest rotation shift that works).
  bool factorize(double mass_coefficient, double stiffness_coefficient);
  /// du_ = A^-1 b with the current factor, its time added to phases.linear_solve; ok is false
  /// if the solve fails or du_ is not finite.
  LinearSolveReport solveSystem(const Eigen::VectorXd& b, StepPhaseTimes& phases);

  ConnectiveCoupling& coupling_;
  CoupledSolverSettings settings_;
  CholmodSolver solver_;
  bool analysed_ = false;
  bool material_only_ = false;
  Eigen::SparseMatrix<double> system_;
  Eigen::VectorXd velocity_, rhs_, du_, product_;
  CoupledState start_, trial_;
};

}  // namespace surgical_sim::core
