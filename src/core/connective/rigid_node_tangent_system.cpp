#include "surgical_sim/core/connective/rigid_node_tangent_system.h"

#include <algorithm>
#include <cmath>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/solve/dirichlet_projection.h"

namespace surgical_sim::core {

void RigidNodeTangentSystem::buildSystem(const RigidNodeProblem& problem,
                                         const RigidNodeConfiguration& q, bool geometric,
                                         double mass_coefficient, double stiffness_coefficient) {
  const RigidNodeModel& model = *problem.model;
  RigidNodeTangentOptions options;
  options.geometric = geometric;
  Stopwatch watch;
  internal_.setZero(model.numDofs());
  model.addInternalForceAndStiffness(q, options, internal_, stiffness_);
  if (geometric) model.addBodyForceStiffness(q, problem.body_acceleration, true, stiffness_);
  phases_.forces += watch.seconds();
  watch.restart();
  system_.coeffs() = stiffness_coefficient * stiffness_.coeffs();
  if (mass_coefficient != 0.0) system_.coeffs() += mass_coefficient * mass_.coeffs();
  projectDirichletMatrix(mask_, system_);
  rotation_scale_ = 0.0;
  for (const int k : rotation_diagonal_) rotation_scale_ += std::abs(system_.valuePtr()[k]);
  if (!rotation_diagonal_.empty())
    rotation_scale_ /= static_cast<double>(rotation_diagonal_.size());
  phases_.assembly += watch.seconds();
}

bool RigidNodeTangentSystem::factorizeShifted(double relative_shift) {
  shifted_.coeffs() = system_.coeffs();
  const double shift = relative_shift * rotation_scale_;
  for (const int k : rotation_diagonal_) shifted_.valuePtr()[k] += shift;
  shift_ = relative_shift;
  return timed(phases_.factorization, [&]() { return solver_.factorize(shifted_); });
}

bool RigidNodeTangentSystem::assemble(const RigidNodeProblem& problem,
                                      const RigidNodeConfiguration& q, double mass_coefficient,
                                      double stiffness_coefficient) {
  const RigidNodeModel& model = *problem.model;
  phases_ = StepPhaseTimes{};
  if (analysed_ != &model || system_.rows() != model.numDofs() ||
      system_.nonZeros() != model.stiffnessPattern().nonZeros()) {
    stiffness_ = model.stiffnessPattern();
    mass_ = stiffness_;
    system_ = stiffness_;
    shifted_ = stiffness_;
    solver_.analyzePattern(system_);
    analysed_ = &model;
  }
  mask_.assign(model.numDofs(), 0);
  markDirichletDofs(problem.fixed_dofs, mask_);
  rotation_diagonal_.clear();
  const int* outer = system_.outerIndexPtr();
  const int* inner = system_.innerIndexPtr();
  for (int d = 3; d < model.numDofs(); d += (d % kRigidNodeDofs == 5 ? 4 : 1)) {
    if (mask_[d] != 0) continue;
    rotation_diagonal_.push_back(
        static_cast<int>(std::lower_bound(inner + outer[d], inner + outer[d + 1], d) - inner));
  }
  if (mass_coefficient != 0.0) timed(phases_.assembly, [&]() { model.assembleNodeMass(q, mass_); });
  bool ok = false;
  for (const bool geometric : {true, false}) {
    material_only_ = !geometric;
    buildSystem(problem, q, geometric, mass_coefficient, stiffness_coefficient);
    for (const double shift : kRotationShifts) {
      ok = factorizeShifted(shift);
      if (ok) break;
    }
    if (ok) break;
  }
  force_ = internal_;
  model.addBodyForce(q, problem.body_acceleration, force_);
  if (problem.external_force.size() != 0) force_ += problem.external_force;
  return ok;
}

LinearSolveReport RigidNodeTangentSystem::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (x.size() != b.size()) x.setZero(b.size());
  LinearSolveReport report = solver_.solve(b, x);
  report.ok = report.ok && x.allFinite();
  return report;
}

}  // namespace surgical_sim::core
