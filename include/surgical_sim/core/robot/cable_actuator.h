#pragma once

#include <vector>

#include "surgical_sim/core/robot/chain_actuator.h"
#include "surgical_sim/core/robot/continuum_robot_description.h"

namespace surgical_sim::core {

/// Cable routed from the base vertebra through one eyelet per vertebra up to last_vertebra; the
/// eyelets sit in each vertebra's mid-plane at (0, r cos angle, r sin angle) of its frame.
/// measure() = -L(q), L the routing polyline length [m]; with tension lambda [N] the force on
/// eyelet k is lambda (u_out - u_in) (u: unit segment directions), on the last one -lambda u_in,
/// mapped to the rigid node as (force, lever x force).
class CableActuator final : public ChainActuator {
 public:
  /// @param cable validated cable description.
  explicit CableActuator(const CableDescription& cable);

  const std::string& name() const override { return name_; }
  double lowerBound() const override { return 0.0; }
  double upperBound() const override { return upper_; }
  double measure(const std::vector<RigidNodePose>& nodes) const override;
  int numPieces() const override { return last_vertebra_; }
  int pieceFirstNode(int piece) const override { return piece; }
  void addPieceGradient(const std::vector<RigidNodePose>& nodes, int piece, double scale,
                        Eigen::Matrix<double, 12, 1>& g12) const override;

 private:
  std::string name_;
  double upper_;
  int last_vertebra_;
  Eigen::Vector3d eyelet_N_;  ///< eyelet in its vertebra's frame [m]
};

}  // namespace surgical_sim::core
