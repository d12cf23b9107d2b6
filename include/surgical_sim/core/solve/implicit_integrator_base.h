#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "surgical_sim/core/solve/integrator.h"
#include "surgical_sim/core/solve/linear_solver.h"
#include "surgical_sim/core/solve/step_compliance.h"
#include "surgical_sim/core/solve/system_matrix.h"

namespace surgical_sim::core {

/// Scaffolding shared by the integrators that solve with a system matrix A assembled from the
/// model's stiffness (ImplicitEulerLinearized, and through NewtonIntegratorBase ImplicitEulerNewton
/// and QuasiStaticNewton): the linear solver, A's fixed pattern and its analysis per topology, the
/// Dirichlet mask, the state at the start of the step and its restoration on failure, and the step
/// compliance. A scheme adds only its own equations.
///
/// Step skeleton of a scheme:
///   StepReport report;
///   if (!beginStep(problem, dt, true, state)) return failedStart(report);
///   ... solve, on failure: return restoreState(state, StepStatus::..., report);
///   compliance_.markFactorized(...) or compliance_.markStale(...) on success.
class ImplicitIntegratorBase : public Integrator {
 public:
  /// The scheme's name (Integrator::name()).
  std::string name() const final;
  /// Forgets the pattern and the compliance (the next step re-analyses, re-sizes every buffer).
  void reset() override;
  /// See Integrator::modelChanged: the next beginStep re-reads the model's pattern.
  void modelChanged() final;
  /// dx = scale A^-1 f through compliance_ (see Integrator::applyStepCompliance); a stale
  /// compliance is factorized by factorizeCompliance().
  bool applyStepCompliance(const Eigen::VectorXd& f, Eigen::VectorXd& dx) final;
  ComplianceUse complianceUse() const final { return compliance_use_; }

 protected:
  /// @param name the scheme's name, also used in the error message
  /// @throws std::invalid_argument naming "solver" if linear_solver is null
  ImplicitIntegratorBase(std::unique_ptr<LinearSolver> linear_solver, std::string name);

  /// Starts a step: invalidates the compliance; checks the problem against the state and dt
  /// (finite, and > 0 if dt_must_be_positive); on a new model or stiffness pattern sets up the
  /// pattern, A's analysis and all buffers (resizeWorkspace), except that after modelChanged() a
  /// changed pattern of the same size is adopted (adoptPattern); marks the Dirichlet DOFs in mask_;
  /// saves state.x, state.v in x0_, v0_. Returns false (nothing changed) if the problem or dt is
  /// inconsistent. Allocation-free unless set-up is needed.
  bool beginStep(const DynamicsProblem& problem, double dt, bool dt_must_be_positive,
                 const SimulationState& state);
  /// report with status SolverFailed: the step could not start (beginStep returned false).
  static StepReport failedStart(StepReport report);
  /// Restores the state saved by beginStep and returns report with the given status.
  StepReport restoreState(SimulationState& state, StepStatus status, StepReport report) const;

  /// Sizes the scheme's own work vectors to size (3n) after a set-up (stiffness_ then holds the
  /// model's compressed pattern). Called by beginStep; may allocate.
  virtual void resizeWorkspace(Eigen::Index size) = 0;
  /// Gives the scheme's own matrices the pattern stiffness_ has just taken (set-up, or a changed
  /// pattern adopted after modelChanged()); default none.
  virtual void patternAdopted() {}
  /// Forgets the scheme's cached evaluations of the model (modelChanged); default none.
  virtual void forgetModelEvaluations() {}
  /// Assembles and factorizes the system matrix of the last successful step for a stale
  /// compliance (StepCompliance::markStale); false on failure. Schemes whose step leaves A
  /// factorized (markFactorized) never reach it.
  virtual bool factorizeCompliance() { return false; }

  std::unique_ptr<LinearSolver> solver_;
  const TissueModel* model_ = nullptr;  ///< model of the set-up (nullptr: none)
  SystemMatrix system_;
  Eigen::SparseMatrix<double> stiffness_;  ///< K with the model's pattern (values: last assembly)
  std::vector<std::uint8_t> mask_;         ///< Dirichlet mask of the current / last step, size 3n
  Eigen::VectorXd x0_, v0_;                ///< state at the start of the step [m], [m/s]
  StepCompliance compliance_;

 private:
  void setUp(const TissueModel& model);
  /// The model's pattern: stiffness_, system_ and the solver's analysis (changed: a new pattern of
  /// the set-up's size after modelChanged(), LinearSolver::analyzeChangedPattern, which may keep
  /// the ordering or factor); buffers and the Dirichlet mask stay.
  void adoptPattern(const TissueModel& model, bool changed);

  bool model_changed_ = false;  ///< modelChanged() since the last beginStep

  std::string name_;
  ComplianceUse compliance_use_;
};

}  // namespace surgical_sim::core
