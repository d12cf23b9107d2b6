#include "surgical_sim/core/solve/mechanical_energy.h"

namespace surgical_sim::core {

double kineticEnergy(const Eigen::VectorXd& mass, const Eigen::VectorXd& v) {
  return 0.5 * (mass.array() * v.array().square()).sum();
}

double mechanicalEnergy(const TissueModel& model, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& v, const Eigen::VectorXd& external_force) {
  return kineticEnergy(model.lumpedMass(), v) + model.energy(x) - external_force.dot(x);
}

}  // namespace surgical_sim::core
