#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <unordered_map>
#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/block_sparsity.h"
#include "surgical_sim/core/tissue/corotational_law.h"
#include "surgical_sim/core/tissue/efg_grid.h"
#include "surgical_sim/core/tissue/efg_options.h"
#include "surgical_sim/core/tissue/group_assembled_model.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {

/// A replacement neighbourhood of one integration point (EfgModel::setNeighbourhoods).
struct EfgNeighbourhood {
  int ip = -1;                 ///< integration point index in [0, m)
  std::vector<int> particles;  ///< distinct particle indices, 4 to EfgOptions::kMaxNeighbours
  /// Kernel distance r_a [m] of each particle (e.g. its distance along the topology graph), each
  /// >= the Euclidean rest distance from the IP (to round-off); empty: the Euclidean distances.
  std::vector<double> distances;
  double volume = 0.0;  ///< inside volume [m^3], finite and >= 0 (0: the IP adds nothing)
};

/// Meshless Element-Free Galerkin tissue: co-rotated linear elasticity, total Lagrangian, on the
/// two regular grids of EfgGrid (DOFs = the grid particles, one-point quadrature at each
/// integration cell's IP weighted by its inside volume V_e).
///
/// Each integration point (IP) e has a set of particles (initially the k = options.neighbours of
/// grid().neighbours; setNeighbourhoods changes it, 4 to EfgOptions::kMaxNeighbours particles)
/// with linear-basis MLS shape functions phi_a and rest gradients g_a = d phi_a / dX
/// (computeMlsShapeFunctions, kernel distances r_a = Euclidean distance + a per-particle detour,
/// zero until a neighbourhood is replaced), so F_e = sum_a x_a g_a^T. With the IP rotation R_e:
/// - Polar: R = rotation of F (CorotationalLaw): psi = mu |F - R|^2 + lambda/2 tr(R^T F - I)^2,
///   force = -dE/dx exactly; Exact mode is the exact Hessian, ProjectedSpd the fixed-R tangent.
/// - ShapeMatching: R = rotation of A = sum_a w_a (x_a - x_c)(X_a - X_c)^T / (tr A_qq / 3), the
///   kernel-weighted (w_a) shape matching of the neighbour particles; strain
///   eps = sym(R^T F) - I, P = R (2 mu eps + lambda tr(eps) I), force f_a = -V_e P g_a. The
///   stiffness (both modes) is the fixed-R tangent R K0 R^T: exact at rest and under rigid
///   motions; away from them it omits dR/dx, a term proportional to the stress.
/// Mass: m_e = rho V_e spread to the IP's particles in proportion to phi_a^2 (positive even where
/// phi_a < 0, sums to rho V_e per IP). bodyForce is consistent: f_a = sum_e rho V_e phi_a(x_e) a.
/// Dirichlet conditions act on particles (MLS is not interpolating: fixing the particles of a
/// face clamps it approximately). Energy, force and stiffness evaluation allocate nothing.
class EfgModel final : public GroupAssembledModel {
 public:
  /// @param mesh Tet4 or Tet10 mesh [m] of the body (only its corner tets are used, to decide
  ///        which volume samples are inside).
  /// @param material validated material (E [Pa], nu [-], rho [kg/m^3]).
  /// @param options grid and shape-function settings (EfgOptions::validate).
  /// @throws std::invalid_argument for invalid material / options / mesh (see buildEfgGrid), or
  ///         when an IP's MLS moment matrix is ill-conditioned (names the IP and the status).
  EfgModel(const TetMesh& mesh, const Material& material, const EfgOptions& options);
  /// The body inside the closed triangle surface `surface` [m] (buildEfgGrid(surface, options));
  /// otherwise as above.
  EfgModel(const TriMesh& surface, const Material& material, const EfgOptions& options);

  std::string name() const override { return "efg"; }
  Eigen::VectorXd bodyForce(const Eigen::Vector3d& a) const override;
  double energy(const Eigen::VectorXd& x) const override;
  void addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const override;
  /// One pass over the IPs: each IP's rotation serves its force, stiffness and energy.
  double addInternalForceStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode,
                                            Eigen::VectorXd& f,
                                            Eigen::SparseMatrix<double>& K) const override;
  /// y = K(x) v [N], y resized to 3n.
  void applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                      Eigen::VectorXd& y) const override;
  /// Particle a: rotation (signed polar) of sum_e V_e F_e over the IPs e that have a among their
  /// neighbours (identity for a particle of no IP).
  bool nodeRotations(const Eigen::VectorXd& x,
                     std::vector<Eigen::Matrix3d>& rotations) const override;

  const EfgOptions& options() const { return options_; }
  /// The grids: particles (= restPositions()), IPs, their current volumes (setNeighbourhoods) and
  /// their initial neighbours (each IP's in ascending particle order; ipParticles() gives the
  /// current ones).
  const EfgGrid& grid() const { return grid_; }
  int numIntegrationPoints() const { return static_cast<int>(ip_particles_.size()); }
  /// Current particles of IP e, ascending, size k_e in [4, EfgOptions::kMaxNeighbours].
  const std::vector<int>& ipParticles(int e) const { return ip_particles_[static_cast<size_t>(e)]; }
  /// phi_a(x_e) [-] of IP e's particles (ipParticles(e)), size k_e.
  Eigen::Map<const Eigen::VectorXd> shapeValues(int e) const;
  /// d phi_a / dX at IP e [1/m], k_e x 3.
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3>> shapeGradients(int e) const;
  /// Kernel distance minus Euclidean rest distance of IP e's particles [m], size k_e (>= 0).
  Eigen::Map<const Eigen::VectorXd> detours(int e) const;
  /// Kernel support radius h of IP e [m].
  double support(int e) const { return support_[static_cast<size_t>(e)]; }
  /// MLS weights of the rest point X [m] with IP e's current particles, support and detours,
  /// evaluated at X: `particles` = ipParticles(e), `weights` their phi_a(X) (sum 1; a linear field
  /// of the particles is reproduced exactly). A point too far from the IP for an invertible moment
  /// matrix with the IP's support (the remapping can give a surface vertex an IP beyond a cut,
  /// cells away) gets the support kernel_support x max_a (|X - X_a| + detour_a), which reaches it
  /// from every particle; only a coplanar set falls back to the IP's own weights shapeValues(e).
  /// Allocates only to grow the outputs.
  /// @throws std::invalid_argument naming "ip" outside [0, m).
  void pointWeights(int e, const Eigen::Vector3d& X, std::vector<int>& particles,
                    std::vector<double>& weights) const;
  /// MLS weights of rest points (e.g. mesh or surface vertices): point i follows the model as
  /// sum_a W(i, a) x_a, with pointWeights of the IP whose cell contains it (the nearest IP when
  /// that cell was dropped). Allocates. @param points rest positions [m], 3 x p. @return W, p x n.
  Eigen::SparseMatrix<double> interpolation(const Eigen::Matrix3Xd& points) const;

  /// Replaces the particles, kernel distances and volumes of the listed IPs (each at most once)
  /// and recomputes, for those IPs only, phi, grad phi, the shape-matching weights, the support
  /// h = kernel_support x max r_a, and their lumped-mass and body-force contributions (old ones
  /// removed, new ones added: total mass is conserved when the volumes sum to the same total).
  /// Only the listed IPs change group (IPs with equal particle sets form one group). The
  /// stiffness pattern couples every pair of particles that has shared an IP since construction:
  /// it grows (linear in its size) only when a new particle set couples an uncoupled pair, and is
  /// otherwise kept, so a solver keeps its analysis (Integrator::modelChanged()). The DOFs are
  /// unchanged. Strong guarantee: on a throw the model is unchanged.
  /// @throws std::invalid_argument naming the IP and the problem: index out of range or repeated,
  ///         a particle count outside [4, EfgOptions::kMaxNeighbours], a particle index out of
  ///         range or repeated, distances of the wrong size, non-finite or shorter than the
  ///         Euclidean distance, a negative or non-finite volume, or an MLS status other than ok.
  void setNeighbourhoods(const std::vector<EfgNeighbourhood>& changes);

 private:
  /// The model on `grid` (built with `options`).
  EfgModel(EfgGrid grid, const Material& material, const EfgOptions& options);
  /// IPs with the same particles form a group (with 8 neighbours: the 8 IPs of a DOF cell), whose
  /// stiffness and force are summed before one scatter. The groups of one particle count k form a
  /// bucket: group g holds the IPs members[g] on the particles nodes[k g .. k g + k).
  struct GroupBucket {
    int k = 0;                              ///< particles per group
    std::vector<std::vector<int>> members;  ///< per group: its IPs
    std::vector<int> nodes;                 ///< k per group
    /// k x k per group (col-major): the sum of its IPs' stabilisation matrices S_e [N/m].
    std::vector<double> stabilization;
    BlockScatterMap scatter;
    int groups() const { return static_cast<int>(members.size()); }
    const int* groupNodes(int g) const { return nodes.data() + static_cast<size_t>(k) * g; }
  };
  /// Hash of a particle set (ipParticles() of an IP).
  struct ParticleSetHash {
    size_t operator()(const std::vector<int>& particles) const;
  };
  /// One MLS evaluation of IP e (computeIp's result) before it is stored.
  struct IpShape;

  template <int K>
  double energyImpl(const GroupBucket& bucket, const Eigen::VectorXd& x) const;
  template <int K>
  void forceImpl(const GroupBucket& bucket, const Eigen::VectorXd& x, Eigen::VectorXd& f) const;
  /// Group stiffness matrices (the sum over the group's IPs) passed to sink(g, Ke); with a
  /// non-null f, also f += the force; with a non-null energy, *energy += the bucket's elastic
  /// energy [J].
  template <int K, typename Sink>
  void stiffnessImpl(const GroupBucket& bucket, const Eigen::VectorXd& x, TangentMode mode,
                     Eigen::VectorXd* f, double* energy, Sink&& sink) const;
  /// addGroupStiffness with, for a non-null energy, *energy = the elastic energy [J].
  void addGroupStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                                  double* values, double* energy) const;
  /// Calls body(bucket, std::integral_constant<int, K>()) per bucket, K = 8 or Eigen::Dynamic.
  template <typename Body>
  void forEachBucket(Body&& body) const;
  /// MLS shape functions and shape-matching weights of IP e with `particles` and `detours`.
  /// @throws std::invalid_argument naming the IP on an MLS status other than ok.
  IpShape computeIp(int e, const std::vector<int>& particles, const Eigen::VectorXd& detours) const;
  /// Stores `shape` as IP e's data (slot grown if needed).
  void storeIp(int e, std::vector<int> particles, const IpShape& shape);
  /// Stabilisation matrix S_e of IP e [N/m], k_e x k_e: its energy is 1/2 sum_ab S_ab u_a . u_b
  /// (EfgOptions::stabilization), S_e = 2 c mu V_e C^T C / sum_a |X_a - X_e|^2 with
  /// C_ab = delta_ab - phi_b - grad phi_b . (X_a - X_e), so C maps the particles' positions to
  /// their distances from the IP's affine prediction (zero for an affine motion).
  Eigen::MatrixXd ipStabilization(int e) const;
  /// Adds sign x IP e's stabilisation matrix to the sum of its group g in bucket b (as addIpMass
  /// does for the mass: a member is subtracted when it leaves and added when it joins).
  void addIpStabilization(int e, GroupBucket& b, int g, double sign) const;
  /// Adds sign x IP e's lumped-mass and body-force contributions.
  void addIpMass(int e, double sign);
  /// Takes IP e out of the group of its particles (a group left empty is removed).
  void leaveGroup(int e);
  /// Puts the IPs `ips` (in no group) into the groups of their particles, creating the missing
  /// groups; couples the particles of new groups in the pattern (rebuilt, with every scatter
  /// map, only when that adds a pair) and sets the new groups' scatter maps.
  void joinGroups(const std::vector<int>& ips);
  /// One IP pass for the stiffness and, with f, the force.
  void addGroupStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                         double* values) const override;
  /// Shape-matching rotation of IP e at nodal positions xe (3 x k).
  template <typename Nodes>
  Eigen::Matrix3d matchingRotation(const Nodes& xe, int e) const;
  /// Linear stress R (2 mu eps + lambda tr(eps) I) of eps = sym(R^T F) - I [Pa].
  Eigen::Matrix3d rotatedStress(const Eigen::Matrix3d& F, const Eigen::Matrix3d& R) const;
  /// Energy density [J/m^3] of the shape-matching strain eps = sym(R^T F) - I.
  double matchingEnergyDensity(const Eigen::Matrix3d& F, const Eigen::Matrix3d& R) const;

  EfgOptions options_;
  CorotationalLaw law_;
  double mu_;       ///< [Pa]
  double lambda_;   ///< [Pa]
  double density_;  ///< [kg/m^3]
  EfgGrid grid_;
  Eigen::VectorXd body_weight_;                 ///< n, sum_e rho V_e phi_a(x_e) [kg]
  std::vector<std::vector<int>> ip_particles_;  ///< per IP, ascending
  /// Per IP: first entry of its slot in the per-particle arrays below (k_e entries used, a
  /// capacity of slot_capacity_ entries; a grown IP gets a new slot at the end).
  std::vector<size_t> slot_;
  std::vector<int> slot_capacity_;
  std::vector<double> shape_values_;  ///< per slot entry: phi [-]
  std::vector<double> detours_;       ///< per slot entry: kernel distance - Euclidean [m]
  std::vector<double> gradients_;     ///< per IP at 3 slot: d phi / dX, k_e x 3 col-major [1/m]
  std::vector<double> matching_;      ///< per IP at 3 slot: shape-matching weights, k_e x 3 [1/m]
  std::vector<double> support_;       ///< per IP: kernel support radius h [m]
  std::vector<GroupBucket> buckets_;  ///< index k: groups of k particles (none for k < 4)
  /// Group index (in bucket size()) of each particle set in use.
  std::unordered_map<std::vector<int>, int, ParticleSetHash> group_of_set_;
};

}  // namespace surgical_sim::core
