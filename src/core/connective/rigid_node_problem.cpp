#include "surgical_sim/core/connective/rigid_node_problem.h"

#include <sstream>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

void checkRigidNodeProblem(const RigidNodeProblem& problem) {
  if (problem.model == nullptr)
    throw std::invalid_argument("RigidNodeProblem.model is null: a model is required");
  const int dofs = problem.model->numDofs();
  if (problem.external_force.size() != 0 && problem.external_force.size() != dofs) {
    std::ostringstream msg;
    msg << "RigidNodeProblem.external_force has size " << problem.external_force.size()
        << ": must be empty or " << dofs << " (6 per rigid node)";
    throw std::invalid_argument(msg.str());
  }
  if (!problem.external_force.allFinite())
    throw std::invalid_argument("RigidNodeProblem.external_force is not finite");
  if (!problem.body_acceleration.allFinite())
    throw std::invalid_argument("RigidNodeProblem.body_acceleration is not finite");
  for (const int d : problem.fixed_dofs) {
    if (d < 0 || d >= dofs) {
      std::ostringstream msg;
      msg << "RigidNodeProblem.fixed_dofs: " << d << " is out of range: must be in [0, " << dofs
          << ")";
      throw std::invalid_argument(msg.str());
    }
  }
  requireNonNegative("RigidNodeProblem.mass_damping", problem.mass_damping, "1/s");
  requireNonNegative("RigidNodeProblem.stiffness_damping", problem.stiffness_damping, "s");
}

}  // namespace surgical_sim::core
