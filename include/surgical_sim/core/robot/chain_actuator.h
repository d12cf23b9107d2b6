#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "surgical_sim/core/robot/rigid_node_pose.h"

namespace surgical_sim::core {

/// An actuator acting on the rigid nodes of a continuum robot through a scalar "actuator
/// displacement" m(q) whose work conjugate is the actuation lambda: the generalized force is
/// lambda dm/dq and the potential -lambda m(q). The row of J_a is dm/dq.
/// Pressure chamber: m = cavity volume [m^3], lambda = gauge pressure [Pa].
/// Cable: m = -(routing length) [m], lambda = tension [N].
class ChainActuator {
 public:
  virtual ~ChainActuator() = default;
  virtual const std::string& name() const = 0;
  /// Actuation bounds [Pa] or [N].
  virtual double lowerBound() const = 0;
  virtual double upperBound() const = 0;
  /// m(q) for the poses of all rigid nodes (index 0 = base), frame robot_base.
  virtual double measure(const std::vector<RigidNodePose>& nodes) const = 0;
  /// g += scale dm/dq; g is node-major over all rigid nodes including the base, size 6(n+1):
  /// (force x,y,z, torque x,y,z) per node [N/unit, N m/unit], frame robot_base. Allocation-free.
  void addGradient(const std::vector<RigidNodePose>& nodes, double scale,
                   Eigen::Ref<Eigen::VectorXd> g) const {
    Eigen::Matrix<double, 12, 1> piece;
    for (int k = 0; k < numPieces(); ++k) {
      piece.setZero();
      addPieceGradient(nodes, k, scale, piece);
      g.segment<12>(6 * pieceFirstNode(k)) += piece;
    }
  }
  /// m is a sum of pieces, each depending on two consecutive rigid nodes only.
  virtual int numPieces() const = 0;
  /// First of the two rigid nodes piece k depends on.
  virtual int pieceFirstNode(int piece) const = 0;
  /// g12 += scale d(m_piece)/d(q_first, q_first+1), shape 12.
  virtual void addPieceGradient(const std::vector<RigidNodePose>& nodes, int piece, double scale,
                                Eigen::Matrix<double, 12, 1>& g12) const = 0;
};

}  // namespace surgical_sim::core
