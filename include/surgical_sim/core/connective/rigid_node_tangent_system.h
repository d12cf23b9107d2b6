#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/connective/rigid_node_problem.h"
#include "surgical_sim/core/solve/cholmod_solver.h"
#include "surgical_sim/core/solve/conjugate_gradient.h"

namespace surgical_sim::core {

/// Relative shifts of the rotational diagonal tried in turn by RigidNodeTangentSystem (see
/// there), times the mean free rotational diagonal entry.
constexpr double kRotationShifts[] = {1e-6, 1e-4, 1e-2};

/// The linear system of one rigid-node Newton / implicit step, A = c_M M(q) + c_K K(q), solved
/// by CHOLMOD: K is the symmetrized tangent (material + geometric, plus the body-force term),
/// M the rigid-node mass (RigidNodeModel::assembleNodeMass); rows and columns of fixed DOFs are
/// projected out (unit diagonal). The pattern is analysed once per model.
///
/// Weights that reproduce linear fields (tet barycentric, trilinear) leave rigid-node rotations
/// that move no sample: with sum_i w_i (p - x_i) = 0, rotating every node of a grid plane about
/// the plane's normal (or, for tets, the nodes' rotations theta_i = theta_0 + beta x_i) changes
/// neither p_s nor F_s at rest, so K and M are singular along these "drilling" modes, and nearly
/// so once deformed (where the body-force term can make them slightly negative). The free
/// rotational diagonal entries of A are therefore shifted by kRotationShifts[k] times their mean
/// (a Levenberg-Marquardt shift on the rotations only, the smallest that factorizes); if no
/// shift makes A positive definite, the free translational diagonal entries are shifted too, by
/// the same factors times their mean (a node whose weights barely reach any sample, e.g. a grid
/// corner outside a round body, is nearly free in translation: its pivot is then at round-off,
/// positive or not depending on the BLAS kernel); if that fails too (compression can make the
/// geometric part indefinite), A is rebuilt without the geometric part (material tangent only)
/// and both tried again. The shift changes increments, never the residual, so equilibria are
/// unchanged.
class RigidNodeTangentSystem {
 public:
  /// f_total = f_int(q) + body force + external force, K, M (if mass_coefficient != 0) and the
  /// factor of the projected A. Returns false if neither A could be factorized.
  bool assemble(const RigidNodeProblem& problem, const RigidNodeConfiguration& q,
                double mass_coefficient, double stiffness_coefficient);
  /// As assemble(), but keeps the factor of the last factorizing assemble() instead of
  /// refactorizing: A is built with that factorization's choice of geometric part and relative
  /// rotational shift (solve it with solveWithKeptFactor()). Returns false, with nothing
  /// assembled, if there is no factor of this model.
  bool assembleKeepingFactor(const RigidNodeProblem& problem, const RigidNodeConfiguration& q,
                             double mass_coefficient, double stiffness_coefficient);
  /// x ~= A^-1 b for the A of the last assemble*() by conjugate gradients from x = 0,
  /// preconditioned with the kept factor: ok when |b - A x| <= relative_tolerance |b| within
  /// max_iterations (iterations counts them, relative_residual reports the last iterate).
  LinearSolveReport solveWithKeptFactor(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                        double relative_tolerance, int max_iterations);
  /// x = A^-1 b (b zero on fixed DOFs gives x zero there). ok is false if the solve fails or
  /// x is not finite.
  LinearSolveReport solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// x ~= A0^-1 b with A0 the projected system WITHOUT the rotational shift (the consistent
  /// Newton matrix; the shift would damp soft modes and make Newton linear): solve() gives the
  /// start, then preconditioned MINRES on A0 (which may be indefinite: drilling modes under
  /// load) with the shifted factor as preconditioner refines it until the preconditioned
  /// residual falls below relative_tolerance or after max_iterations. The refined x is kept if
  /// it lowers |b - A0 x|, else solve()'s. ok as solve(); iterations counts the MINRES
  /// iterations + 1; relative_residual is |b - A0 x| / |b|. Allocation-free after the first call.
  LinearSolveReport solveUnshifted(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                   double relative_tolerance, int max_iterations);

  const Eigen::VectorXd& totalForce() const { return force_; }
  /// Internal force alone (part of totalForce()).
  const Eigen::VectorXd& internalForce() const { return internal_; }
  /// Unprojected symmetrized tangent of the last assemble().
  const Eigen::SparseMatrix<double>& stiffness() const { return stiffness_; }
  /// Rigid-node mass of the last assemble() with mass_coefficient != 0.
  const Eigen::SparseMatrix<double>& mass() const { return mass_; }
  /// Whether the last factorization dropped the geometric part.
  bool usedMaterialTangentOnly() const { return material_only_; }
  /// The relative rotational shift of the last factorization (an entry of kRotationShifts).
  double rotationShift() const { return shift_; }
  /// Whether the last factorization shifted the translational diagonal too.
  bool shiftedTranslations() const { return shift_translations_; }
  /// Wall time of the last assemble(): forces (the sample loop: force, tangent, gravity
  /// tangent), assembly (mass and A), factorization (every shift tried); linear_solve 0.
  const StepPhaseTimes& phases() const { return phases_; }
  /// The fixed-DOF mask (1 = fixed) of the last assemble().
  const std::vector<std::uint8_t>& fixedMask() const { return mask_; }

 private:
  /// internal_, stiffness_ and the projected, unshifted system_; rotation_scale_ and
  /// translation_scale_.
  void buildSystem(const RigidNodeProblem& problem, const RigidNodeConfiguration& q, bool geometric,
                   double mass_coefficient, double stiffness_coefficient);
  /// Analyses model's pattern if new; the fixed-DOF mask, rotation_diagonal_ and
  /// translation_diagonal_.
  void prepare(const RigidNodeProblem& problem);
  /// force_ = internal_ + body force + external force at q.
  void addLoads(const RigidNodeProblem& problem, const RigidNodeConfiguration& q);
  /// shifted_ = system_ with the rotational shift (and the translational one when
  /// shift_translations_).
  void shiftSystem(double relative_shift);
  /// Factorizes system_ with the shifts of shiftSystem into shifted_.
  bool factorizeShifted(double relative_shift);

  const RigidNodeModel* analysed_ = nullptr;
  CholmodSolver solver_;
  Eigen::SparseMatrix<double> stiffness_, mass_, system_, shifted_;
  std::vector<int> rotation_diagonal_;     ///< value indices of free rotational diagonal entries
  double rotation_scale_ = 0.0;            ///< mean |entry| there [N m/rad]
  std::vector<int> translation_diagonal_;  ///< value indices of free translational ones
  double translation_scale_ = 0.0;         ///< mean |entry| there [N/m]
  double shift_ = 0.0;
  bool shift_translations_ = false;
  Eigen::VectorXd force_, internal_, refined_;
  Eigen::VectorXd minres_[7];  ///< work vectors of solveUnshifted
  std::vector<std::uint8_t> mask_;
  bool material_only_ = false;
  bool factorized_ = false;  ///< the last factorizing assemble() succeeded
  CgWorkspace cg_;           ///< work vectors of solveWithKeptFactor
  StepPhaseTimes phases_;
};

}  // namespace surgical_sim::core
