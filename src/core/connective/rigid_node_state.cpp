#include "surgical_sim/core/connective/rigid_node_state.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "surgical_sim/core/robot/so3.h"

namespace surgical_sim::core {

void applyRigidNodeIncrement(const Eigen::VectorXd& dq, double scale,
                             RigidNodeConfiguration& config) {
  const int n = config.numNodes();
  if (dq.size() != kRigidNodeDofs * n) {
    std::ostringstream msg;
    msg << "applyRigidNodeIncrement: increment size " << dq.size() << " must be 6 x " << n
        << " rigid nodes";
    throw std::invalid_argument(msg.str());
  }
  for (int i = 0; i < n; ++i) {
    config.p_TN[i] += scale * dq.segment<3>(kRigidNodeDofs * i);
    const Eigen::Vector3d dtheta = scale * dq.segment<3>(kRigidNodeDofs * i + 3);
    config.q_TN[i] = (expRotation(dtheta) * config.q_TN[i]).normalized();
  }
}

void checkRigidNodeConfiguration(const RigidNodeConfiguration& config, const char* what) {
  if (config.q_TN.size() != config.p_TN.size()) {
    std::ostringstream msg;
    msg << what << ": " << config.p_TN.size() << " positions but " << config.q_TN.size()
        << " orientations";
    throw std::invalid_argument(msg.str());
  }
  for (int i = 0; i < config.numNodes(); ++i) {
    if (!config.p_TN[i].allFinite()) {
      std::ostringstream msg;
      msg << what << ": rigid node " << i << " position (" << config.p_TN[i].transpose()
          << ") m is not finite";
      throw std::invalid_argument(msg.str());
    }
    const double norm = config.q_TN[i].norm();
    if (!(std::abs(norm - 1.0) <= 1e-6)) {
      std::ostringstream msg;
      msg << what << ": rigid node " << i << " quaternion norm " << norm
          << " is out of range: must be 1 (within 1e-6)";
      throw std::invalid_argument(msg.str());
    }
  }
}

}  // namespace surgical_sim::core
