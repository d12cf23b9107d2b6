#include "surgical_sim/bench/beam_tip_deflection.h"

#include <Eigen/SparseCore>
#include <limits>
#include <vector>

#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"

namespace surgical_sim::bench {

DirichletBc clampNodes(const std::vector<int>& nodes, const Eigen::VectorXd& x) {
  DirichletBc bc;
  for (const int v : nodes)
    for (int k = 0; k < 3; ++k) bc.dofs.push_back(3 * v + k);
  bc.positions.resize(static_cast<Eigen::Index>(bc.dofs.size()));
  for (std::size_t i = 0; i < bc.dofs.size(); ++i)
    bc.positions[static_cast<Eigen::Index>(i)] = x[bc.dofs[i]];
  return bc;
}

double beamTipDeflection(const TissueModel& model, const Eigen::Vector3d& load) {
  const Eigen::VectorXd& rest = model.restPositions();
  const int n = model.numNodes();
  double length = 0.0;
  for (int v = 0; v < n; ++v) length = std::max(length, rest[3 * v]);
  std::vector<int> clamped;
  std::vector<Eigen::Triplet<double>> tip;
  for (int v = 0; v < n; ++v) {
    const double x = rest[3 * v];
    if (x <= 1e-9 * length) clamped.push_back(v);
    if (x >= length * (1.0 - 1e-9)) tip.emplace_back(static_cast<int>(tip.size()), v, 1.0);
  }
  Eigen::SparseMatrix<double> weights(static_cast<Eigen::Index>(tip.size()), n);
  weights.setFromTriplets(tip.begin(), tip.end());
  return beamTipDeflection(model, load, clamped, weights);
}

double beamTipDeflection(const TissueModel& model, const Eigen::Vector3d& load,
                         const std::vector<int>& clamped, const Eigen::SparseMatrix<double>& tip) {
  const Eigen::VectorXd& rest = model.restPositions();
  DynamicsProblem problem;
  problem.model = &model;
  problem.external_force = model.bodyForce(load);
  problem.dirichlet = clampNodes(clamped, rest);
  problem.damping.mass_coefficient = 1e3;  // [1/s]: heavily overdamped relaxation
  SimulationState state{rest, Eigen::VectorXd::Zero(rest.size()), 0.0};
  const auto integrator = makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {},
                                         makeLinearSolver(SolverKind::Cholmod, {}));
  const Eigen::Vector3d direction = load.normalized();
  const Eigen::Index points = tip.rows();
  auto tipDeflection = [&] {
    const Eigen::VectorXd u = state.x - rest;
    const Eigen::Map<const Eigen::Matrix3Xd> U(u.data(), 3, model.numNodes());
    const Eigen::Matrix3Xd at_tip = U * tip.transpose();  // 3 x points
    return (direction.transpose() * at_tip).sum() / static_cast<double>(points);
  };
  double previous = 0.0;
  for (int step = 0; step < 500; ++step) {
    const StepStatus status = integrator->step(problem, 1.0, state).status;
    if (status != StepStatus::Ok && status != StepStatus::NotConverged)
      return std::numeric_limits<double>::quiet_NaN();
    const double w = tipDeflection();
    if (step > 0 && std::abs(w - previous) <= 1e-9 * std::abs(w)) return w;
    previous = w;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace surgical_sim::bench
