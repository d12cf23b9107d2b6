#pragma once

#include <memory>
#include <vector>

#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// Sum of tissue models sharing one node set (e.g. soft sections + stiff vertebrae of the full
/// FE robot plant, each an FeModel with its own material over a subset of the elements).
/// Energy, forces, masses and stiffness are the sums of the parts; the stiffness pattern is the
/// union of the parts' patterns, filled through precomputed scatter maps (allocation-free).
class SummedTissueModel final : public TissueModel {
 public:
  /// @param parts at least one model, all with the same rest positions.
  /// @throws std::invalid_argument "summed_tissue_model.parts" if empty or the node sets differ.
  explicit SummedTissueModel(std::vector<std::unique_ptr<TissueModel>> parts);

  std::string name() const override { return "summed"; }
  const Eigen::VectorXd& restPositions() const override { return parts_[0]->restPositions(); }
  const Eigen::VectorXd& lumpedMass() const override { return mass_; }
  Eigen::VectorXd bodyForce(const Eigen::Vector3d& a) const override;
  double energy(const Eigen::VectorXd& x) const override;
  void addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const override;
  const Eigen::SparseMatrix<double>& stiffnessPattern() const override { return pattern_; }
  void assembleStiffness(const Eigen::VectorXd& x, TangentMode mode,
                         Eigen::SparseMatrix<double>& K) const override;
  void applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                      Eigen::VectorXd& y) const override;

 private:
  std::vector<std::unique_ptr<TissueModel>> parts_;
  Eigen::VectorXd mass_;
  Eigen::SparseMatrix<double> pattern_;
  std::vector<std::vector<int>> scatter_;                    ///< part value index -> pattern_ index
  mutable std::vector<Eigen::SparseMatrix<double>> part_k_;  ///< per-part assembly buffers
  mutable Eigen::VectorXd work_;                             ///< applyStiffness buffer
};

}  // namespace surgical_sim::core
