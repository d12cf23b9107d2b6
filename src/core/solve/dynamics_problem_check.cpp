#include "surgical_sim/core/solve/dynamics_problem_check.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace surgical_sim::core {

const char* findProblemError(const DynamicsProblem& problem, const SimulationState& state) {
  if (problem.model == nullptr) return "problem.model is null";
  const Eigen::Index size = problem.model->restPositions().size();
  if (state.x.size() != size) return "state.x must have size 3n (3 x number of model nodes)";
  if (state.v.size() != size) return "state.v must have size 3n (3 x number of model nodes)";
  if (problem.external_force.size() != size) {
    return "problem.external_force must have size 3n (3 x number of model nodes)";
  }
  if (!state.x.allFinite() || !state.v.allFinite()) return "state.x and state.v must be finite";
  if (!problem.external_force.allFinite()) return "problem.external_force [N] must be finite";
  const RayleighDamping& damping = problem.damping;
  if (!std::isfinite(damping.mass_coefficient) || damping.mass_coefficient < 0.0) {
    return "problem.damping.mass_coefficient [1/s] must be finite and >= 0";
  }
  if (!std::isfinite(damping.stiffness_coefficient) || damping.stiffness_coefficient < 0.0) {
    return "problem.damping.stiffness_coefficient [s] must be finite and >= 0";
  }
  const DirichletBc& bc = problem.dirichlet;
  if (bc.positions.size() != static_cast<Eigen::Index>(bc.dofs.size())) {
    return "problem.dirichlet.positions must have one entry per problem.dirichlet.dofs entry";
  }
  for (const int dof : bc.dofs) {
    if (dof < 0 || dof >= size) return "problem.dirichlet.dofs entries must be in [0, 3n)";
  }
  if (!bc.positions.allFinite()) return "problem.dirichlet.positions [m] must be finite";
  return nullptr;
}

void validateDynamicsProblem(const DynamicsProblem& problem, const SimulationState& state) {
  const char* error = findProblemError(problem, state);
  if (error != nullptr) throw std::invalid_argument(std::string(error));
}

}  // namespace surgical_sim::core
