#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

#include "surgical_sim/core/connective/rigid_node_problem.h"
#include "surgical_sim/core/solve/cholmod_solver.h"

namespace surgical_sim::core {

/// The linear system of one rigid-node Newton / implicit step, A = c_M M(q) + c_K K(q), solved
/// by CHOLMOD: K is the symmetrized tangent (material + geometric, plus the body-force term),
/// M the consistent mass; rows and columns of fixed DOFs are projected out (unit diagonal).
/// If A is not positive definite (compression can make the geometric part indefinite), it is
/// rebuilt without the geometric part (material tangent only, positive semi-definite) and
/// factorized again. The pattern is analysed once per model.
class RigidNodeTangentSystem {
 public:
  /// f_total = f_int(q) + body force + external force, K, M (if mass_coefficient != 0) and the
  /// factor of the projected A. Returns false if neither A could be factorized.
  bool assemble(const RigidNodeProblem& problem, const RigidNodeConfiguration& q,
                double mass_coefficient, double stiffness_coefficient);
  /// x = A^-1 b (b zero on fixed DOFs gives x zero there). ok is false if the solve fails or
  /// x is not finite.
  LinearSolveReport solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);

  const Eigen::VectorXd& totalForce() const { return force_; }
  /// Internal force alone (part of totalForce()).
  const Eigen::VectorXd& internalForce() const { return internal_; }
  /// Unprojected symmetrized tangent of the last assemble().
  const Eigen::SparseMatrix<double>& stiffness() const { return stiffness_; }
  /// Consistent mass of the last assemble() with mass_coefficient != 0.
  const Eigen::SparseMatrix<double>& mass() const { return mass_; }
  /// Whether the last factorization dropped the geometric part.
  bool usedMaterialTangentOnly() const { return material_only_; }
  /// The fixed-DOF mask (1 = fixed) of the last assemble().
  const std::vector<std::uint8_t>& fixedMask() const { return mask_; }

 private:
  bool factorizeWith(const RigidNodeProblem& problem, const RigidNodeConfiguration& q,
                     bool geometric, double mass_coefficient, double stiffness_coefficient);

  const RigidNodeModel* analysed_ = nullptr;
  CholmodSolver solver_;
  Eigen::SparseMatrix<double> stiffness_, mass_, system_;
  Eigen::VectorXd force_, internal_;
  std::vector<std::uint8_t> mask_;
  bool material_only_ = false;
};

}  // namespace surgical_sim::core
