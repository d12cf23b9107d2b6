#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/corotational_law.h"
#include "surgical_sim/core/tissue/efg_grid.h"
#include "surgical_sim/core/tissue/efg_options.h"
#include "surgical_sim/core/tissue/group_assembled_model.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {

/// Meshless Element-Free Galerkin tissue: co-rotated linear elasticity, total Lagrangian, on the
/// two regular grids of EfgGrid (DOFs = the grid particles, one-point quadrature at each
/// integration cell's IP weighted by its inside volume V_e).
///
/// Each integration point (IP) e has k = options.neighbours particles with linear-basis MLS shape
/// functions phi_a and rest gradients g_a = d phi_a / dX (computeMlsShapeFunctions), so
/// F_e = sum_a x_a g_a^T. With the IP rotation R_e:
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
  /// The grids: particles (= restPositions()), IPs, their volumes and neighbours (each IP's in
  /// ascending particle order).
  const EfgGrid& grid() const { return grid_; }
  /// phi_a(x_e) [-] of IP e's neighbours (grid().neighbours.col(e)), size k.
  Eigen::Map<const Eigen::VectorXd> shapeValues(int e) const;
  /// d phi_a / dX at IP e [1/m], k x 3.
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3>> shapeGradients(int e) const;
  /// MLS weights of rest points (e.g. mesh or surface vertices): point i follows the model as
  /// sum_a W(i, a) x_a. Each point uses the particles and kernel support of the IP whose cell
  /// contains it (the nearest IP when that cell was dropped), with the MLS functions evaluated at
  /// the point, so rows sum to 1 and a linear motion of the particles moves the points exactly.
  /// Allocates. @param points rest positions [m], 3 x p. @return W, p x n.
  Eigen::SparseMatrix<double> interpolation(const Eigen::Matrix3Xd& points) const;

 private:
  /// The model on `grid` (built with `options`).
  EfgModel(EfgGrid grid, const Material& material, const EfgOptions& options);
  template <int K>
  double energyImpl(const Eigen::VectorXd& x) const;
  template <int K>
  void forceImpl(const Eigen::VectorXd& x, Eigen::VectorXd& f) const;
  /// Group stiffness matrices (the sum over the group's IPs) passed to sink(g, Ke); with a
  /// non-null f, also f += the force; with a non-null energy, *energy = the elastic energy [J].
  template <int K, typename Sink>
  void stiffnessImpl(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f, double* energy,
                     Sink&& sink) const;
  /// addGroupStiffness with the energy (see stiffnessImpl).
  void addGroupStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                                  double* values, double* energy) const;
  /// Groups the IPs that share their particles (grid().neighbours column): group_ips_,
  /// group_first_, group_nodes_.
  void groupIntegrationPoints();
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
  double mu_;      ///< [Pa]
  double lambda_;  ///< [Pa]
  EfgGrid grid_;
  int k_;                             ///< neighbours per IP
  Eigen::VectorXd body_weight_;       ///< n, sum_e rho V_e phi_a(x_e) [kg]
  std::vector<double> shape_values_;  ///< per IP: phi, k
  std::vector<double> gradients_;     ///< per IP: d phi / dX, k x 3 col-major [1/m]
  std::vector<double> matching_;      ///< per IP: shape-matching weights, k x 3 col-major [1/m]
  std::vector<double> support_;       ///< per IP: kernel support radius h [m]
  /// IPs with the same particles form a group (with 8 neighbours: the 8 IPs of a DOF cell), whose
  /// stiffness and force are summed before one scatter: group g holds IPs
  /// group_ips_[group_first_[g] .. group_first_[g + 1]) on particles group_nodes_.col(g).
  std::vector<int> group_ips_;
  std::vector<int> group_first_;  ///< size groups + 1
  Eigen::MatrixXi group_nodes_;   ///< k x groups
};

}  // namespace surgical_sim::core
