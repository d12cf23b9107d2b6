#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

namespace surgical_sim::core {

/// True if A and B are compressed, of one size, with nonzeros at the same positions (values
/// ignored). Linear in the nonzeros; allocation-free.
bool samePattern(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& B);

/// System matrix A = a diag(m) + b K (+ c K2 ...) of the implicit integrators, stored with a
/// fixed pattern: the model's stiffness pattern united with the diagonal. setPattern() builds the
/// pattern and the index maps once per topology; assembly then only writes values (no
/// allocation), so a LinearSolver analyses A's pattern once.
class SystemMatrix {
 public:
  /// Builds A's pattern from the model's 3n x 3n stiffness pattern (full, symmetric) plus the
  /// diagonal, and the maps stiffness entry -> A entry and row -> diagonal entry. Allocates.
  void setPattern(const Eigen::SparseMatrix<double>& stiffness_pattern);

  /// True if stiffness_pattern has the size and number of entries setPattern() was built from.
  bool matchesPattern(const Eigen::SparseMatrix<double>& stiffness_pattern) const;

  /// A = mass_coefficient diag(mass) + stiffness_coefficient K.
  /// @param mass lumped mass [kg], size 3n
  /// @param mass_coefficient [-] (dimension chosen by the caller's scaling)
  /// @param K stiffness [N/m] with the pattern given to setPattern()
  /// @param stiffness_coefficient [s^2] or [-], as the caller's scaling requires
  void assemble(const Eigen::VectorXd& mass, double mass_coefficient,
                const Eigen::SparseMatrix<double>& K, double stiffness_coefficient);

  /// A += coefficient K (K with the pattern given to setPattern()).
  void addStiffness(const Eigen::SparseMatrix<double>& K, double coefficient);

  /// Dirichlet projection of A (see projectDirichletMatrix); mask of size 3n.
  void projectDirichlet(const std::vector<std::uint8_t>& mask);

  /// The assembled matrix, 3n x 3n, compressed, full symmetric pattern.
  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }

 private:
  Eigen::SparseMatrix<double> matrix_;
  std::vector<int> stiffness_to_system_;  ///< entry k of K -> entry of A
  std::vector<int> diagonal_entry_;       ///< row i -> entry (i, i) of A
  Eigen::Index stiffness_nonzeros_ = -1;
};

}  // namespace surgical_sim::core
