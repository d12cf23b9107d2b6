#include "surgical_sim/core/robot/cable_actuator.h"

#include <cmath>

namespace surgical_sim::core {

CableActuator::CableActuator(const CableDescription& cable)
    : name_(cable.name),
      upper_(cable.tension_max),
      last_vertebra_(cable.last_vertebra),
      eyelet_N_(0.0, cable.radial_offset * std::cos(cable.angle),
                cable.radial_offset * std::sin(cable.angle)) {}

double CableActuator::measure(const std::vector<RigidNodePose>& nodes) const {
  double length = 0.0;
  Eigen::Vector3d prev = nodes[0].p_BN + nodes[0].q_BN * eyelet_N_;
  for (int k = 1; k <= last_vertebra_; ++k) {
    const Eigen::Vector3d e = nodes[k].p_BN + nodes[k].q_BN * eyelet_N_;
    length += (e - prev).norm();
    prev = e;
  }
  return -length;
}

void CableActuator::addPieceGradient(const std::vector<RigidNodePose>& nodes, int piece,
                                     double scale, Eigen::Matrix<double, 12, 1>& g12) const {
  // m_piece = -|e_b - e_a|: dm/de_a = u, dm/de_b = -u, u = (e_b - e_a) / |e_b - e_a|.
  const Eigen::Vector3d lever_a = nodes[piece].q_BN * eyelet_N_;
  const Eigen::Vector3d lever_b = nodes[piece + 1].q_BN * eyelet_N_;
  const Eigen::Vector3d u =
      ((nodes[piece + 1].p_BN + lever_b) - (nodes[piece].p_BN + lever_a)).normalized();
  g12.segment<3>(0) += scale * u;
  g12.segment<3>(3) += scale * lever_a.cross(u);
  g12.segment<3>(6) -= scale * u;
  g12.segment<3>(9) -= scale * lever_b.cross(u);
}

}  // namespace surgical_sim::core
