#pragma once

#include <vector>

#include "surgical_sim/core/robot/chain_actuator.h"
#include "surgical_sim/core/robot/continuum_robot_description.h"

namespace surgical_sim::core {

/// Pneumatic chamber (Bosman eqs 5.20-5.22): in every gap it spans, a closed triangulated
/// cylinder whose caps lie on the two vertebra faces. Cap vertices move with their vertebra;
/// lateral-wall vertices at axial fraction t are skinned, p = (1-t)(p_A + R_A a) + t(p_B + R_B b).
/// Nodal force per unit pressure f_i = sum_j A_j n_j / 3 over the adjacent triangles (n_j out of
/// the cavity), mapped to the rigid nodes by the transposed skinning Jacobian; this equals
/// d(volume)/dq, so measure() is the cavity volume [m^3] and lambda the gauge pressure [Pa].
/// addPieceGradient uses per-instance scratch buffers (sized in the constructor, no allocation):
/// one instance must not be evaluated from two threads at once.
class PressureChamberActuator final : public ChainActuator {
 public:
  /// @param chamber validated chamber description.
  /// @param robot validated robot description (spacing, thickness).
  /// @param angular_segments vertices per cavity ring [-], >= 3.
  /// @param axial_segments ring layers along one cavity [-], >= 1.
  /// @throws std::invalid_argument naming "pressure_chamber.angular_segments" /
  ///         "pressure_chamber.axial_segments".
  PressureChamberActuator(const PressureChamberDescription& chamber,
                          const ContinuumRobotDescription& robot, int angular_segments,
                          int axial_segments);

  const std::string& name() const override { return name_; }
  double lowerBound() const override { return lower_; }
  double upperBound() const override { return upper_; }
  double measure(const std::vector<RigidNodePose>& nodes) const override;
  int numPieces() const override { return static_cast<int>(piece_begin_.size()) - 1; }
  int pieceFirstNode(int piece) const override { return first_gap_ + piece; }
  void addPieceGradient(const std::vector<RigidNodePose>& nodes, int piece, double scale,
                        Eigen::Matrix<double, 12, 1>& g12) const override;

  /// Cavity surface vertices at the given rigid-node poses [m], frame robot_base (allocates; for
  /// set-up, e.g. embedding the cavity in the full FE plant).
  std::vector<Eigen::Vector3d> vertexPositions(const std::vector<RigidNodePose>& nodes) const;
  /// Cavity triangles (vertex indices), oriented out of the cavity.
  const std::vector<Eigen::Vector3i>& triangles() const { return triangles_; }

 private:
  struct Vertex {
    int node_a;           ///< proximal rigid node
    double t;             ///< skinning weight of the distal node a+1 [-]
    Eigen::Vector3d a_A;  ///< rest position in node a's frame [m]
    Eigen::Vector3d b_B;  ///< rest position in node a+1's frame [m]
  };
  Eigen::Vector3d position(const std::vector<RigidNodePose>& nodes, const Vertex& v) const;

  std::string name_;
  double lower_;
  double upper_;
  std::vector<Vertex> vertices_;
  std::vector<Eigen::Vector3i> triangles_;  ///< outward (out of the cavity) orientation
  std::vector<int> piece_begin_;            ///< first triangle of each gap (+ end)
  std::vector<int> vertex_begin_;           ///< first vertex of each gap (+ end)
  int first_gap_;
  /// Scratch of addPieceGradient per vertex of one gap: R_A a_A, R_B b_B, position, force [m, N].
  mutable std::vector<Eigen::Vector3d> r_a_, r_b_, p_, f_;
};

}  // namespace surgical_sim::core
