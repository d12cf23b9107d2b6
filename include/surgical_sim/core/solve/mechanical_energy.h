#pragma once

#include <Eigen/Core>

#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// Total mechanical energy [J] = kinetic 0.5 v^T M v + elastic W(x) - f_ext . x (potential of a
/// constant external force). x [m], v [m/s], external_force [N], all size 3n. Allocation-free
/// apart from what model.energy() does (nothing, by the TissueModel contract).
double mechanicalEnergy(const TissueModel& model, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& v, const Eigen::VectorXd& external_force);

/// Kinetic energy 0.5 v^T M v [J] with the lumped mass [kg] (size 3n) and v [m/s] (size 3n).
double kineticEnergy(const Eigen::VectorXd& mass, const Eigen::VectorXd& v);

}  // namespace surgical_sim::core
