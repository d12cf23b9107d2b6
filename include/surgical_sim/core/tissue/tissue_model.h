#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

namespace surgical_sim::core {

/// How the tangent stiffness is assembled.
enum class TangentMode {
  Exact,         ///< K = -df/dx exactly (may be indefinite under compression / inversion)
  ProjectedSpd,  ///< each element's contribution projected to positive semi-definite (for solvers)
};

/// Common interface of every tissue model (mass-spring, FEM laws, EMS, later meshless / 6-DoF).
///
/// Vectors of positions, velocities and forces are node-major, size 3n: (x0, y0, z0, x1, ...),
/// in metres / m/s / newtons, expressed in the tissue rest frame.
/// Implementations precompute everything per topology in their constructor; force and stiffness
/// evaluation allocate nothing.
class TissueModel {
 public:
  virtual ~TissueModel() = default;

  /// Short identifier, e.g. "corotational", "neo_hookean", "svk", "ems", "mass_spring".
  virtual std::string name() const = 0;

  /// Rest positions [m], size 3n.
  virtual const Eigen::VectorXd& restPositions() const = 0;
  int numNodes() const { return static_cast<int>(restPositions().size() / 3); }

  /// Diagonal lumped mass [kg], size 3n (the same value repeated for x, y, z of a node). Positive.
  virtual const Eigen::VectorXd& lumpedMass() const = 0;

  /// Consistent nodal force of a uniform body acceleration a [m/s^2] (e.g. gravity):
  /// f_i = integral(rho N_i dV) a [N], size 3n. Sums to total mass times a.
  virtual Eigen::VectorXd bodyForce(const Eigen::Vector3d& a) const = 0;

  /// Elastic strain energy [J] at positions x (size 3n).
  virtual double energy(const Eigen::VectorXd& x) const = 0;

  /// f += internal elastic force [N] at x: the restoring force -dE/dx.
  virtual void addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const = 0;

  /// Sparsity pattern of the 3n x 3n stiffness (full, symmetric, compressed column). Fixed for a
  /// given topology; assembleStiffness writes into a matrix with exactly this pattern.
  virtual const Eigen::SparseMatrix<double>& stiffnessPattern() const = 0;

  /// Writes K = -df/dx [N/m] at x into the values of K, which must have stiffnessPattern().
  virtual void assembleStiffness(const Eigen::VectorXd& x, TangentMode mode,
                                 Eigen::SparseMatrix<double>& K) const = 0;

  /// addInternalForce(x, f) and assembleStiffness(x, mode, K) in one call (f is added to, K
  /// overwritten), equal to the separate calls to round-off. The default makes the two calls;
  /// models whose force and stiffness share per-element work override it with one pass.
  virtual void addInternalForceAndStiffness(const Eigen::VectorXd& x, TangentMode mode,
                                            Eigen::VectorXd& f,
                                            Eigen::SparseMatrix<double>& K) const {
    addInternalForce(x, f);
    assembleStiffness(x, mode, K);
  }

  /// addInternalForceAndStiffness(x, mode, f, K) and energy(x) in one call, returning the energy
  /// [J]; equal to the separate calls to round-off. The default makes the two calls; models whose
  /// energy shares the per-element work of the force (the rotation of a corotational element)
  /// override it with one pass.
  virtual double addInternalForceStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode,
                                                    Eigen::VectorXd& f,
                                                    Eigen::SparseMatrix<double>& K) const {
    addInternalForceAndStiffness(x, mode, f, K);
    return energy(x);
  }

  /// Operator form: y = K(x) v without assembling a global matrix (element by element).
  virtual void applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                              Eigen::VectorXd& y) const = 0;

  /// Per-node rotations at x (size 3n) relative to the rest state, for preconditioners that warp a
  /// factor of another state's matrix (pcg_cholesky_warped): rotations[i] is the rotation of node
  /// i's local deformation (a rigid motion x = R X + t gives R at every node, the rest state the
  /// identity). Resizes rotations to n (allocates only when the size changes). Returns false
  /// (rotations untouched) if the model defines none, the default.
  virtual bool nodeRotations(const Eigen::VectorXd& /*x*/,
                             std::vector<Eigen::Matrix3d>& /*rotations*/) const {
    return false;
  }
};

}  // namespace surgical_sim::core
