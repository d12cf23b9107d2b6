#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "surgical_sim/core/connective/rigid_node_shape_functions.h"
#include "surgical_sim/core/connective/rigid_node_state.h"

namespace surgical_sim::core {

/// Most rigid nodes one sample may depend on (fixed-size per-sample work arrays).
constexpr int kMaxSampleNeighbours = 16;

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

/// An integration sample of a connective layer: a point at rest position p_s carrying volume v_s
/// and its own St Venant-Kirchhoff material, skinned from its neighbouring rigid nodes.
struct RigidNodeSample {
  Eigen::Vector3d rest_position = Eigen::Vector3d::Zero();  ///< p_s at rest [m], in T
  double volume = 0.0;    ///< v_s [m^3], > 0; the samples' volumes sum to the layer's volume
  double lambda = 0.0;    ///< Lame's first parameter [Pa], >= 0
  double mu = 0.0;        ///< shear modulus [Pa], > 0
  double density = 0.0;   ///< [kg/m^3], > 0
  SampleWeights weights;  ///< at most kMaxSampleNeighbours nodes, a partition of unity
};

/// What assembleStiffness() assembles of the tangent K = -df/dq (6n x 6n, convention of
/// RigidNodeConfiguration).
struct RigidNodeTangentOptions {
  bool material = true;    ///< sum_s v_s M_is^T C M_ks
  bool geometric = true;   ///< stress terms: sum_s v_s S_jl B_ij^T B_kl plus the rotation term
  bool symmetrize = true;  ///< (K + K^T) / 2 (the rotation term alone is not symmetric)
};

/// Per-sample kinematics at a configuration (for inspection and tests): the deformation
/// gradient, and per neighbour a the 9 x 6 Jacobian B_a = dF/dq_a (rows 3 j .. 3 j + 2: column j
/// of F) and the 6 x 6 strain Jacobian M_a = d{E}/dq_a (Voigt order 00, 11, 22, 12, 02, 01,
/// engineering shear).
struct SampleKinematics {
  Eigen::Matrix3d F;
  std::vector<Eigen::Matrix<double, 9, 6>> B;
  std::vector<Matrix6d> M;
};

/// Bosman's connective-tissue model: rigid nodes (position + orientation, 6 DOFs) and integration
/// samples whose motion is skinned from them (linear blend, total Lagrangian):
///   p_s = sum_i w_is (x_i + R_i lbar_is),   lbar_is = Rbar_i^T (pbar_s - xbar_i),
///   F_s = sum_i (x_i + R_i lbar_is) grad w_is^T + w_is R_i Rbar_i^T,
///   E_s = (F^T F - I) / 2,   S_s = lambda tr(E) I + 2 mu E,
///   W = sum_s v_s (lambda/2 tr(E)^2 + mu E:E),   f_i = -sum_s M_is^T {S_s} v_s = -dW/dq_i.
/// All vectors follow RigidNodeConfiguration's convention (6 entries per node, spatial angular
/// increments). The tangent K = -df/dq = dW/dq is positive semi-definite at rest; its geometric
/// rotation-rotation blocks are not symmetric (spatial increments are not coordinates), so
/// assembleStiffness symmetrizes on request. Precomputes per (node, sample) pair at
/// construction; evaluation allocates nothing (but sampleKinematics). Configurations passed to
/// the evaluation functions must have numNodes() nodes with unit quaternions (not checked
/// there: checkRigidNodeConfiguration); vectors and matrices of the wrong size throw.
///
/// This is not a TissueModel: its unknowns are 6 per node and orientations are updated
/// multiplicatively (applyRigidNodeIncrement), not by adding to a 3n vector. Its solvers are
/// RigidNodeQuasiStatic and RigidNodeImplicitEuler.
class RigidNodeModel {
 public:
  /// @param rest rest configuration (unit quaternions, finite positions)
  /// @param samples at least one; each validated (volume, Lame parameters, density, weights:
  ///        checkSampleWeights, at most kMaxSampleNeighbours), and every rigid node must be a
  ///        neighbour of some sample
  /// @throws std::invalid_argument naming the sample or node and the bad value
  RigidNodeModel(const RigidNodeConfiguration& rest, const std::vector<RigidNodeSample>& samples);

  int numNodes() const { return rest_.numNodes(); }
  int numSamples() const { return static_cast<int>(samples_.size()); }
  int numDofs() const { return kRigidNodeDofs * numNodes(); }
  const RigidNodeConfiguration& restConfiguration() const { return rest_; }
  const std::vector<RigidNodeSample>& samples() const { return samples_; }
  /// Sum of the sample volumes [m^3] and of their masses rho_s v_s [kg].
  double totalVolume() const;
  double totalMass() const;

  /// Position [m] of a point with weights w (rest position rest_point) under the skinning map;
  /// w must pass checkSampleWeights for numNodes() (not checked).
  Eigen::Vector3d mapPoint(const RigidNodeConfiguration& q, const SampleWeights& w,
                           const Eigen::Vector3d& rest_point) const;
  /// Position of sample s [m].
  Eigen::Vector3d samplePosition(const RigidNodeConfiguration& q, int s) const;
  /// F, B and M of sample s at q (allocates).
  SampleKinematics sampleKinematics(const RigidNodeConfiguration& q, int s) const;
  /// PK2 stress {S} of sample s for deformation gradient F, Voigt (00, 11, 22, 12, 02, 01) [Pa].
  Vector6d sampleStress(int s, const Eigen::Matrix3d& F) const;

  /// Elastic energy W [J].
  double energy(const RigidNodeConfiguration& q) const;
  /// f += -dW/dq [N, N m], size numDofs().
  void addInternalForce(const RigidNodeConfiguration& q, Eigen::VectorXd& f) const;
  /// Full symmetric 6n x 6n pattern (6 x 6 blocks for every pair of nodes sharing a sample).
  const Eigen::SparseMatrix<double>& stiffnessPattern() const { return pattern_; }
  /// K = -df/dq [N/m, N, N m/rad] at q into the values of K (which must have
  /// stiffnessPattern()), the parts of `options`.
  void assembleStiffness(const RigidNodeConfiguration& q, const RigidNodeTangentOptions& options,
                         Eigen::SparseMatrix<double>& K) const;
  /// addInternalForce and assembleStiffness in one pass over the samples.
  void addInternalForceAndStiffness(const RigidNodeConfiguration& q,
                                    const RigidNodeTangentOptions& options, Eigen::VectorXd& f,
                                    Eigen::SparseMatrix<double>& K) const;

  /// Consistent generalized force of a uniform acceleration a [m/s^2] on the sample masses:
  /// f_i += sum_s m_s w_is a, torque_i += sum_s m_s w_is (R_i lbar_is) x a.
  void addBodyForce(const RigidNodeConfiguration& q, const Eigen::Vector3d& a,
                    Eigen::VectorXd& f) const;
  /// Potential of that force, -sum_s m_s a . p_s [J].
  double bodyForcePotential(const RigidNodeConfiguration& q, const Eigen::Vector3d& a) const;
  /// K += -d(body force)/dq: on node i's rotation block -sum_s m_s w_is [a]x [R_i lbar_is]x
  /// (symmetric part only if symmetrize). K must have stiffnessPattern().
  void addBodyForceStiffness(const RigidNodeConfiguration& q, const Eigen::Vector3d& a,
                             bool symmetrize, Eigen::SparseMatrix<double>& K) const;

  /// Consistent mass [kg, kg m, kg m^2] at q from the sample masses m_s = rho_s v_s:
  /// M_ik = sum_s m_s w_is w_ks J_is^T J_ks with J_is = [I, -[R_i lbar_is]x] (the sample velocity
  /// is sum_i w_is J_is qdot_i), so qdot^T M qdot / 2 is the samples' kinetic energy. Symmetric,
  /// positive semi-definite, written into M (which must have stiffnessPattern()).
  void assembleMass(const RigidNodeConfiguration& q, Eigen::SparseMatrix<double>& M) const;
  /// Rigid-node mass [kg, kg m, kg m^2] at q: one 6 x 6 block per node, M_i = sum_s m_s w_is
  /// J_is^T J_is (each sample's mass shared among its nodes by weight, carried rigidly by the
  /// node: its translational mass, first moment and inertia tensor about x_i). Gives the exact
  /// kinetic energy of rigid motions at rest (x_i + R_i lbar_is = p_s) and is positive definite
  /// for any node whose samples are not collinear with it, also along the drilling modes where
  /// assembleMass is singular (see RigidNodeTangentSystem). Written into M (stiffnessPattern(),
  /// off-diagonal blocks zero).
  void assembleNodeMass(const RigidNodeConfiguration& q, Eigen::SparseMatrix<double>& M) const;

 private:
  struct Pair {
    int node = 0;
    double weight = 0.0;
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    Eigen::Vector3d local_offset = Eigen::Vector3d::Zero();  ///< lbar_is [m]
  };
  /// Per-pair rotating part A = R lbar grad w^T + w R Rbar^T (column j: a_ij), R lbar, and F.
  int sampleFrame(const RigidNodeConfiguration& q, int s, Eigen::Matrix3d* A, Eigen::Vector3d* r,
                  Eigen::Matrix3d& F) const;
  void evaluate(const RigidNodeConfiguration& q, const RigidNodeTangentOptions* options,
                Eigen::VectorXd* f, Eigen::SparseMatrix<double>* K) const;
  /// values[block (node of pair a, node of pair b) of sample s] += Kab.
  void scatter(int s, int a, int b, const Matrix6d& Kab, double* values) const;
  void checkMatrix(const Eigen::SparseMatrix<double>& K, const char* what) const;
  void checkVector(const Eigen::VectorXd& f, const char* what) const;

  RigidNodeConfiguration rest_;
  std::vector<RigidNodeSample> samples_;
  std::vector<Eigen::Matrix3d> rest_rotation_transposed_;  ///< Rbar_i^T per node
  std::vector<Pair> pairs_;
  std::vector<int> pair_begin_;  ///< sample s owns pairs [pair_begin_[s], pair_begin_[s + 1])
  /// Whether sample s ends a run of consecutive samples with the same rigid nodes (in order).
  std::vector<char> run_ends_;
  Eigen::SparseMatrix<double> pattern_;
  /// Per sample, per (a, b) of its pairs: value index of row 6 node_b in column 6 node_a.
  std::vector<int> block_first_;
  std::vector<int> block_begin_;     ///< sample s's entries start at block_begin_[s]
  std::vector<int> column_length_;   ///< per node: entries in each of its 6 columns
  std::vector<int> diagonal_first_;  ///< per node: value index of its diagonal block
};

}  // namespace surgical_sim::core
