#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "surgical_sim/core/connective/rigid_node_model.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// An FE organ of a ConnectiveCoupling: any TissueModel (3 DOFs per node). Non-owning.
struct CoupledOrgan {
  const TissueModel* model = nullptr;
  std::vector<int> fixed_nodes;  ///< nodes held at their positions in the state
};

/// A connective layer of a ConnectiveCoupling. Non-owning.
struct CoupledLayer {
  const RigidNodeModel* model = nullptr;
  std::vector<int> fixed_nodes;  ///< rigid nodes held (all 6 DOFs) at their configuration
};

/// Organ nodes that follow a layer by skinning: node b of the organ moves as
///   x_b = sum_j w_bj (p_j + R_j o_bj),   o_bj = Rbar_j^T (X_b - pbar_j),
/// with Shepard weights w_bj = d_bj^-2 / sum d^-2 on the `neighbours` rigid nodes of the layer
/// nearest to its rest position X_b (weight 1 on a rigid node it coincides with, within 1e-9
/// of the largest neighbour distance): a partition of unity, so rigid motions are transmitted
/// exactly.
struct OrganLayerAttachment {
  int organ = 0;
  int layer = 0;
  std::vector<int> nodes;  ///< organ nodes, each attached once and not fixed
  int neighbours = 4;      ///< in [1, layer rigid nodes]
};

/// A spring of stiffness k [N/m] pulling organ node `node` towards `target` [m] (a tool that
/// grasps the node), energy k |x - target|^2 / 2.
struct CoupledSpring {
  int organ = 0;
  int node = 0;
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  double stiffness = 0.0;
};

/// A constant force [N] on organ node `node`.
struct CoupledPointForce {
  int organ = 0;
  int node = 0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
};

/// Loads of one step or solve.
struct CoupledLoads {
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< on every body's mass [m/s^2]
  std::vector<CoupledPointForce> forces;
  std::vector<CoupledSpring> springs;
};

/// State of every body: organ node positions [m] and velocities [m/s] (3n each), layer
/// configurations and 6-DOF velocities (RigidNodeConfiguration's convention), time [s].
/// Attached organ nodes are functions of the layers (ConnectiveCoupling::applyMapping).
struct CoupledState {
  std::vector<Eigen::VectorXd> organ_positions, organ_velocities;
  std::vector<RigidNodeConfiguration> layer_configurations;
  std::vector<Eigen::VectorXd> layer_velocities;
  double time = 0.0;
};

/// What ConnectiveCoupling::assemble builds.
struct CouplingTangentOptions {
  TangentMode organ_mode = TangentMode::ProjectedSpd;
  /// Keep only the symmetric part of the rigid nodes' rotation terms (layer geometric and
  /// gravity terms, the mapping term below), as the SPD solvers need.
  bool symmetrize = true;
  /// Include the stress- and load-dependent rigid-node terms: the layers' geometric and
  /// gravity terms and the mapping term below. Without them K~ is the layers' material
  /// tangent plus the organs' tangents: positive semi-definite whatever the loads.
  bool geometric = true;
};

/// FE organs and connective layers coupled into one mechanical system.
///
/// Unknowns u (node-major): 3 per free organ node (not fixed, not attached), organ by organ,
/// then 6 per free rigid node, layer by layer (RigidNodeConfiguration's convention). Attached
/// organ nodes are not unknowns: their increments follow from their layer's rigid nodes,
///   dx_b = sum_j J_bj dq_j,   J_bj = w_bj [I, -[r_bj]x],   r_bj = R_j o_bj,
/// (fixed rigid nodes contribute no column), so with P the map from u to all organ-node
/// increments, the system's energy is
///   Pi(u) = sum_organs (E_o(x_o) - f_body . x_o - f_point . x_o + springs)
///         + sum_layers (W_l(q_l) + V_gravity,l(q_l)),
/// its generalized force f~ = P^T f_organs + f_layers, and its tangent
///   K~ = P^T K_organs P + K_layers + K_map,   K_map on rigid node j's rotation block:
///   -sum_b w_bj [f_b]x [r_bj]x   (f_b the total organ force on node b: P depends on R_j),
/// and mass M~ = P^T M_organs P + M_layers (lumped organ mass, RigidNodeModel's node mass).
/// K~ and M~ are symmetric (with symmetrize) and share one sparse pattern built once, with
/// precomputed scatter indices, so assembling allocates nothing.
class ConnectiveCoupling {
 public:
  /// @throws std::invalid_argument naming the body or attachment and the bad value (missing
  ///         model, node or layer index out of range, a node attached twice or both attached and
  ///         fixed, neighbours out of range, an organ stiffness pattern without full 3 x 3 node
  ///         blocks)
  ConnectiveCoupling(std::vector<CoupledOrgan> organs, std::vector<CoupledLayer> layers,
                     const std::vector<OrganLayerAttachment>& attachments);

  int numUnknowns() const { return num_unknowns_; }
  int numOrgans() const { return static_cast<int>(organs_.size()); }
  int numLayers() const { return static_cast<int>(layers_.size()); }
  const CoupledOrgan& organ(int o) const { return organs_[o]; }
  const CoupledLayer& layer(int l) const { return layers_[l]; }
  /// Whether organ node a is attached to a layer.
  bool attached(int organ, int node) const { return links_[organ][node].count > 0; }

  /// Rest positions and configurations, zero velocities.
  CoupledState restState() const;
  /// Sets the attached organ nodes' positions from their layers, and their velocities to
  /// sum_j J_bj v_j; zeroes the velocities of fixed organ nodes and fixed rigid nodes.
  /// @throws std::invalid_argument for a state of the wrong shape
  void applyMapping(CoupledState& state) const;

  /// Total potential Pi [J] of state (see the class comment; no kinetic energy).
  double potentialEnergy(const CoupledState& state, const CoupledLoads& loads) const;

  /// Generalized force f~ (size numUnknowns()), the tangent K~ and (if with_mass) M~ at state
  /// (which must be mapped: applyMapping). Also records the norms used by the solvers.
  /// @throws std::invalid_argument for a state of the wrong shape or a load naming a missing
  ///         organ / node or with a negative or non-finite stiffness
  void assemble(const CoupledState& state, const CoupledLoads& loads,
                const CouplingTangentOptions& options, bool with_mass);
  const Eigen::VectorXd& force() const { return force_; }
  const Eigen::SparseMatrix<double>& stiffness() const { return stiffness_; }
  const Eigen::SparseMatrix<double>& mass() const { return mass_; }
  /// |internal forces| + |applied forces| of all bodies (before mapping, springs counted as
  /// applied) at the last assemble [N]: the scale of force() for convergence tests.
  double forceScale() const { return force_scale_; }
  /// Value indices (in stiffness()/mass()) of the diagonal entries of free rigid-node rotations.
  const std::vector<int>& rotationDiagonal() const { return rotation_diagonal_; }

  /// Unknowns of state's velocities (free organ nodes, free rigid nodes) into u.
  void gatherVelocity(const CoupledState& state, Eigen::VectorXd& u) const;
  /// Free organ nodes x += scale du, free rigid nodes q <- q (+) scale du; then applyMapping
  /// (attached velocities from the state's layer velocities).
  void applyIncrement(const Eigen::VectorXd& du, double scale, CoupledState& state) const;
  /// Velocities of the unknowns set from u (attached ones mapped, fixed ones zero).
  void scatterVelocity(const Eigen::VectorXd& u, CoupledState& state) const;

 private:
  struct Skin {
    int layer_node = 0;
    double weight = 0.0;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< o_bj [m]
    int column = -1;                                   ///< first unknown of the rigid node, or -1
  };
  struct Link {
    int layer = -1, begin = 0, count = 0;
  };
  struct Target {
    int column = 0;
    int skin = -1;  ///< index into skins_ (6 columns), or -1 for a free organ node (3 columns)
  };
  struct OrganBlock {
    int a = 0, b = 0;
    std::array<int, 3> value{};  ///< organ value index of (3a, 3b + c)
    int dst = 0;                 ///< first index into dst_ of this block's target pairs
  };

  void checkState(const CoupledState& state) const;
  void checkLoads(const CoupledLoads& loads) const;
  /// r_bj = R_j o_bj and J_bj of every skin at state into rotated_ and jacobian_.
  void rotateOffsets(const CoupledState& state);
  /// Total organ force f_o (internal + gravity + point forces + springs) into organ_force_[o],
  /// its tangent into organ_stiffness_[o] (springs on the diagonal blocks).
  void evaluateOrgan(int o, const CoupledState& state, const CoupledLoads& loads, TangentMode mode);
  /// Adds J_a^T X J_b of every target pair of organ block `block` into values.
  void scatterOrganBlock(int o, const OrganBlock& block, const Eigen::Matrix3d& X,
                         double* values) const;

  std::vector<CoupledOrgan> organs_;
  std::vector<CoupledLayer> layers_;
  int num_unknowns_ = 0;
  int organ_unknowns_ = 0;  ///< unknowns of free organ nodes (the rigid nodes' start after)
  std::vector<std::vector<int>> organ_column_;  ///< per organ node: first unknown, or -1
  std::vector<std::vector<int>> layer_column_;  ///< per rigid node: first unknown, or -1
  /// Per organ node: its layer and skins_ range; attached iff count > 0.
  std::vector<std::vector<Link>> links_;
  std::vector<Skin> skins_;
  std::vector<Eigen::Vector3d> rotated_;               ///< per skin: r_bj at the last rotateOffsets
  std::vector<Eigen::Matrix<double, 3, 6>> jacobian_;  ///< per skin: J_bj there
  std::vector<std::vector<int>> target_begin_;         ///< per organ: per node, into targets_[o]
  std::vector<std::vector<Target>> targets_;
  std::vector<std::vector<OrganBlock>> blocks_;
  std::vector<std::vector<int>> diagonal_block_;  ///< per organ node: its (a, a) block
  std::vector<int> dst_;  ///< per target pair and column of its right target: value index
  std::vector<std::vector<int>> layer_value_;  ///< per layer value: global value index or -1
  /// Per free rigid node (by first unknown / 6 of the layer part): value indices of its
  /// rotation block's columns at its first rotation row.
  std::vector<std::array<int, 3>> rotation_block_;
  std::vector<int> rotation_diagonal_;

  Eigen::SparseMatrix<double> stiffness_, mass_;
  Eigen::VectorXd force_;
  std::vector<Eigen::VectorXd> organ_force_, layer_force_;
  std::vector<Eigen::SparseMatrix<double>> organ_stiffness_, layer_stiffness_, layer_mass_;
  double force_scale_ = 0.0, internal_squared_ = 0.0, applied_squared_ = 0.0;
  std::vector<Eigen::Vector3d> body_gravity_;       ///< gravity of body_force_
  std::vector<Eigen::VectorXd> body_force_;         ///< per organ: bodyForce(body_gravity_[o])
  mutable std::vector<Eigen::VectorXd> increment_;  ///< per layer: 6n work vector
  std::vector<Eigen::VectorXd> work_;               ///< per organ, then per layer: internal force
};

}  // namespace surgical_sim::core
