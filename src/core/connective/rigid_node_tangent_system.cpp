#include "surgical_sim/core/connective/rigid_node_tangent_system.h"

#include "surgical_sim/core/solve/dirichlet_projection.h"

namespace surgical_sim::core {

bool RigidNodeTangentSystem::factorizeWith(const RigidNodeProblem& problem,
                                           const RigidNodeConfiguration& q, bool geometric,
                                           double mass_coefficient, double stiffness_coefficient) {
  const RigidNodeModel& model = *problem.model;
  RigidNodeTangentOptions options;
  options.geometric = geometric;
  internal_.setZero(model.numDofs());
  model.addInternalForceAndStiffness(q, options, internal_, stiffness_);
  if (geometric) model.addBodyForceStiffness(q, problem.body_acceleration, true, stiffness_);
  system_.coeffs() = stiffness_coefficient * stiffness_.coeffs();
  if (mass_coefficient != 0.0) system_.coeffs() += mass_coefficient * mass_.coeffs();
  projectDirichletMatrix(mask_, system_);
  return solver_.factorize(system_);
}

bool RigidNodeTangentSystem::assemble(const RigidNodeProblem& problem,
                                      const RigidNodeConfiguration& q, double mass_coefficient,
                                      double stiffness_coefficient) {
  const RigidNodeModel& model = *problem.model;
  if (analysed_ != &model || system_.rows() != model.numDofs()) {
    stiffness_ = model.stiffnessPattern();
    mass_ = stiffness_;
    system_ = stiffness_;
    solver_.analyzePattern(system_);
    analysed_ = &model;
  }
  mask_.assign(model.numDofs(), 0);
  markDirichletDofs(problem.fixed_dofs, mask_);
  if (mass_coefficient != 0.0) model.assembleMass(q, mass_);
  material_only_ = false;
  bool ok = factorizeWith(problem, q, true, mass_coefficient, stiffness_coefficient);
  if (!ok) {
    material_only_ = true;
    ok = factorizeWith(problem, q, false, mass_coefficient, stiffness_coefficient);
  }
  force_ = internal_;
  model.addBodyForce(q, problem.body_acceleration, force_);
  if (problem.external_force.size() != 0) force_ += problem.external_force;
  return ok;
}

LinearSolveReport RigidNodeTangentSystem::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  LinearSolveReport report = solver_.solve(b, x);
  report.ok = report.ok && x.allFinite();
  return report;
}

}  // namespace surgical_sim::core
