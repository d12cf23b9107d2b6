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
  const auto meanMagnitude = [this](const std::vector<int>& entries) {
    double sum = 0.0;
    for (const int k : entries) sum += std::abs(system_.valuePtr()[k]);
    return entries.empty() ? 0.0 : sum / static_cast<double>(entries.size());
  };
  rotation_scale_ = meanMagnitude(rotation_diagonal_);
  translation_scale_ = meanMagnitude(translation_diagonal_);
  phases_.assembly += watch.seconds();
}

void RigidNodeTangentSystem::shiftSystem(double relative_shift) {
  shifted_.coeffs() = system_.coeffs();
  const double shift = relative_shift * rotation_scale_;
  for (const int k : rotation_diagonal_) shifted_.valuePtr()[k] += shift;
  if (shift_translations_) {
    const double translation_shift = relative_shift * translation_scale_;
    for (const int k : translation_diagonal_) shifted_.valuePtr()[k] += translation_shift;
  }
  shift_ = relative_shift;
}

bool RigidNodeTangentSystem::factorizeShifted(double relative_shift) {
  shiftSystem(relative_shift);
  return timed(phases_.factorization, [&]() { return solver_.factorize(shifted_); });
}

void RigidNodeTangentSystem::prepare(const RigidNodeProblem& problem) {
  const RigidNodeModel& model = *problem.model;
  phases_ = StepPhaseTimes{};
  if (analysed_ != &model || system_.rows() != model.numDofs() ||
      system_.nonZeros() != model.stiffnessPattern().nonZeros()) {
    stiffness_ = model.stiffnessPattern();
    mass_ = stiffness_;
    system_ = stiffness_;
    shifted_ = stiffness_;
    solver_.analyzePattern(system_);
    cg_.resize(model.numDofs());
    analysed_ = &model;
    factorized_ = false;
  }
  mask_.assign(model.numDofs(), 0);
  markDirichletDofs(problem.fixed_dofs, mask_);
  rotation_diagonal_.clear();
  translation_diagonal_.clear();
  const int* outer = system_.outerIndexPtr();
  const int* inner = system_.innerIndexPtr();
  for (int d = 0; d < model.numDofs(); ++d) {
    if (mask_[d] != 0) continue;
    const int k =
        static_cast<int>(std::lower_bound(inner + outer[d], inner + outer[d + 1], d) - inner);
    (d % kRigidNodeDofs < 3 ? translation_diagonal_ : rotation_diagonal_).push_back(k);
  }
}

void RigidNodeTangentSystem::addLoads(const RigidNodeProblem& problem,
                                      const RigidNodeConfiguration& q) {
  force_ = internal_;
  problem.model->addBodyForce(q, problem.body_acceleration, force_);
  if (problem.external_force.size() != 0) force_ += problem.external_force;
}

bool RigidNodeTangentSystem::assemble(const RigidNodeProblem& problem,
                                      const RigidNodeConfiguration& q, double mass_coefficient,
                                      double stiffness_coefficient) {
  const RigidNodeModel& model = *problem.model;
  prepare(problem);
  if (mass_coefficient != 0.0) timed(phases_.assembly, [&]() { model.assembleNodeMass(q, mass_); });
  bool ok = false;
  for (const bool geometric : {true, false}) {
    material_only_ = !geometric;
    buildSystem(problem, q, geometric, mass_coefficient, stiffness_coefficient);
    for (const bool translations : {false, true}) {
      shift_translations_ = translations;
      for (const double shift : kRotationShifts) {
        ok = factorizeShifted(shift);
        if (ok) break;
      }
      if (ok) break;
    }
    if (ok) break;
  }
  addLoads(problem, q);
  factorized_ = ok;
  return ok;
}

bool RigidNodeTangentSystem::assembleKeepingFactor(const RigidNodeProblem& problem,
                                                   const RigidNodeConfiguration& q,
                                                   double mass_coefficient,
                                                   double stiffness_coefficient) {
  if (!factorized_ || analysed_ != problem.model) return false;
  prepare(problem);
  if (!factorized_) return false;
  if (mass_coefficient != 0.0)
    timed(phases_.assembly, [&]() { problem.model->assembleNodeMass(q, mass_); });
  buildSystem(problem, q, !material_only_, mass_coefficient, stiffness_coefficient);
  timed(phases_.assembly, [&]() { shiftSystem(shift_); });
  addLoads(problem, q);
  return true;
}

LinearSolveReport RigidNodeTangentSystem::solveWithKeptFactor(const Eigen::VectorXd& b,
                                                              Eigen::VectorXd& x,
                                                              double relative_tolerance,
                                                              int max_iterations) {
  x.setZero(b.size());
  return preconditionedConjugateGradient(
      shifted_, b, x, max_iterations, relative_tolerance,
      [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) { return solver_.precondition(r, z); },
      cg_);
}

LinearSolveReport RigidNodeTangentSystem::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (x.size() != b.size()) x.setZero(b.size());
  LinearSolveReport report = solver_.solve(b, x);
  report.ok = report.ok && x.allFinite();
  return report;
}

LinearSolveReport RigidNodeTangentSystem::solveUnshifted(const Eigen::VectorXd& b,
                                                         Eigen::VectorXd& x,
                                                         double relative_tolerance,
                                                         int max_iterations) {
  LinearSolveReport report = solve(b, x);
  if (!report.ok) return report;
  const double b_norm = b.norm();
  if (b_norm == 0.0) return report;
  Eigen::VectorXd& r1 = minres_[0];
  Eigen::VectorXd& r2 = minres_[1];
  Eigen::VectorXd& y = minres_[2];
  Eigen::VectorXd& v = minres_[3];
  Eigen::VectorXd& w = minres_[4];
  Eigen::VectorXd& w1 = minres_[5];
  Eigen::VectorXd& w2 = minres_[6];
  r1 = b;
  r1.noalias() -= system_ * x;
  report.relative_residual = r1.norm() / b_norm;
  if (report.relative_residual <= relative_tolerance || max_iterations <= 0) return report;
  // Preconditioned MINRES (Paige and Saunders) on A0 dx = r1 from dx = 0, with the SPD shifted
  // factor as preconditioner: A0 may be indefinite (drilling modes under load).
  refined_.setZero(b.size());
  y.resize(b.size());
  if (!solver_.solveWithFactor(r1, y)) return report;
  const double beta1 = std::sqrt(std::max(r1.dot(y), 0.0));
  if (!(beta1 > 0.0)) return report;
  double beta = beta1, old_beta = 0.0, dbar = 0.0, epsilon = 0.0, phibar = beta1;
  double cs = -1.0, sn = 0.0;
  r2 = r1;
  w.setZero(b.size());
  w2.setZero(b.size());
  int iterations = 0;
  for (; iterations < max_iterations; ++iterations) {
    v = y / beta;
    y.noalias() = system_ * v;
    if (iterations > 0) y -= (beta / old_beta) * r1;
    const double alpha = v.dot(y);
    y -= (alpha / beta) * r2;
    r1.swap(r2);
    r2 = y;
    if (!solver_.solveWithFactor(r2, y)) break;
    old_beta = beta;
    beta = std::sqrt(std::max(r2.dot(y), 0.0));
    const double old_epsilon = epsilon;
    const double delta = cs * dbar + sn * alpha;
    const double gbar = sn * dbar - cs * alpha;
    epsilon = sn * beta;
    dbar = -cs * beta;
    const double gamma = std::max(std::hypot(gbar, beta), 1e-300);
    cs = gbar / gamma;
    sn = beta / gamma;
    const double phi = cs * phibar;
    phibar *= sn;
    w1.swap(w2);
    w2.swap(w);
    w = (v - old_epsilon * w1 - delta * w2) / gamma;
    refined_ += phi * w;
    if (phibar <= relative_tolerance * beta1 || !(beta > 0.0)) {
      ++iterations;
      break;
    }
  }
  refined_ += x;
  r1 = b;
  r1.noalias() -= system_ * refined_;
  const double refined_residual = r1.norm() / b_norm;
  report.iterations += iterations;
  if (refined_.allFinite() && refined_residual < report.relative_residual) {
    x = refined_;
    report.relative_residual = refined_residual;
  }
  return report;
}

}  // namespace surgical_sim::core
