#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "surgical_sim/core/tissue/block_sparsity.h"
#include "surgical_sim/core/tissue/group_schedule.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// A TissueModel whose stiffness is a sum of dense group matrices (elements, springs, the
/// neighbourhoods of integration points) scatter-added into one block pattern. It holds the rest
/// positions, the lumped mass and the pattern, and checks and zeroes K before an assembly; a model
/// only supplies the group matrices (addGroupStiffness). Models that loop over their groups with
/// schedule() use threads() threads (default defaultThreadCount()) with results bit-identical
/// for any thread count.
class GroupAssembledModel : public TissueModel {
 public:
  /// Threads of the group loops (1: the calling thread alone); copies of the model share them.
  /// @throws std::invalid_argument naming "threads" outside [1, kMaxThreads].
  void setThreads(int threads) { schedule_.setThreads(threads); }
  int threads() const { return schedule_.threads(); }
  const Eigen::VectorXd& restPositions() const final { return rest_positions_; }
  const Eigen::VectorXd& lumpedMass() const final { return lumped_mass_; }
  const Eigen::SparseMatrix<double>& stiffnessPattern() const final { return pattern_; }
  /// @throws std::invalid_argument "<name()> model: K must have stiffnessPattern()" if K does not
  ///         have the pattern's size and nonzero count, or is not compressed.
  void assembleStiffness(const Eigen::VectorXd& x, TangentMode mode,
                         Eigen::SparseMatrix<double>& K) const final;
  /// One call of addGroupStiffness with the force. @throws as assembleStiffness.
  void addInternalForceAndStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd& f,
                                    Eigen::SparseMatrix<double>& K) const final;

 protected:
  /// Builds the pattern, the scatter map and the schedule of `groups` (k x g node indices in
  /// [0, num_nodes)).
  /// @throws std::invalid_argument if SURGICAL_SIM_THREADS is invalid (defaultThreadCount).
  void setGroups(int num_nodes, const Eigen::MatrixXi& groups);
  /// Grows the pattern in place by the couplings `added` (growBlockPattern; a model without a
  /// pattern starts from the empty 3n x 3n one, n = added.size()), for a model that never calls
  /// setGroups: it scatters with its own maps and loops over its own groups.
  void growPattern(const std::vector<std::vector<int>>& added);
  /// The parallel order of the groups passed to setGroups.
  const GroupSchedule& schedule() const { return schedule_; }
  /// Scatter-adds every group's stiffness matrix K_g = -df_g/dx_g at x into `values` (the
  /// pattern's value array, zeroed) through scatterGroup(); with a non-null f, also f += the
  /// internal force (in the same pass where the model can).
  virtual void addGroupStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                                 double* values) const = 0;
  /// K's value array, zeroed. @throws as assembleStiffness.
  double* zeroedValues(Eigen::SparseMatrix<double>& K) const;
  /// values[pattern entries of group g] += Ke (3k x 3k, local dof 3 a + i = node a, axis i).
  template <typename Matrix>
  void scatterGroup(int group, const Matrix& Ke, double* values) const {
    scatter_.add(group, Ke, values);
  }

  Eigen::VectorXd rest_positions_;  ///< 3n [m]
  Eigen::VectorXd lumped_mass_;     ///< 3n [kg]

 private:
  Eigen::SparseMatrix<double> pattern_;
  BlockScatterMap scatter_;
  GroupSchedule schedule_;
};

}  // namespace surgical_sim::core
