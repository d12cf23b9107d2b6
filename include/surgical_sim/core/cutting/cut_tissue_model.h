#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "surgical_sim/core/tissue/material.h"
#include "surgical_sim/core/tissue/model_factory.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// A tissue model of a cut (virtual-node) mesh: elasticity from the wrapped model (built on the
/// cutter's mesh, every copy a full element), mass from the cutter (each copy weighted by its
/// material fraction, TetCutter::lumpedMass()). Body force is the lumped mass times the
/// acceleration, which is the consistent body force of Tet4 elements.
class CutTissueModel final : public TissueModel {
 public:
  /// @param elastic model of the cut mesh (not null).
  /// @param lumped_mass [kg], size 3 n of the elastic model, every entry > 0.
  /// @throws std::invalid_argument for a null model or a mass of the wrong size or sign.
  CutTissueModel(std::unique_ptr<TissueModel> elastic, Eigen::VectorXd lumped_mass);

  std::string name() const override { return elastic_->name(); }
  const Eigen::VectorXd& restPositions() const override { return elastic_->restPositions(); }
  const Eigen::VectorXd& lumpedMass() const override { return mass_; }
  Eigen::VectorXd bodyForce(const Eigen::Vector3d& a) const override;
  double energy(const Eigen::VectorXd& x) const override { return elastic_->energy(x); }
  void addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const override {
    elastic_->addInternalForce(x, f);
  }
  const Eigen::SparseMatrix<double>& stiffnessPattern() const override {
    return elastic_->stiffnessPattern();
  }
  void assembleStiffness(const Eigen::VectorXd& x, TangentMode mode,
                         Eigen::SparseMatrix<double>& K) const override {
    elastic_->assembleStiffness(x, mode, K);
  }
  void addInternalForceAndStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd& f,
                                    Eigen::SparseMatrix<double>& K) const override {
    elastic_->addInternalForceAndStiffness(x, mode, f, K);
  }
  double addInternalForceStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode,
                                            Eigen::VectorXd& f,
                                            Eigen::SparseMatrix<double>& K) const override {
    return elastic_->addInternalForceStiffnessAndEnergy(x, mode, f, K);
  }
  void applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                      Eigen::VectorXd& y) const override {
    elastic_->applyStiffness(x, mode, v, y);
  }
  bool nodeRotations(const Eigen::VectorXd& x,
                     std::vector<Eigen::Matrix3d>& rotations) const override {
    return elastic_->nodeRotations(x, rotations);
  }

 private:
  std::unique_ptr<TissueModel> elastic_;
  Eigen::VectorXd mass_;
};

class TetCutter;

/// Tissue model of the cutter's current mesh: makeTissueModel(kind, cutter.mesh(), material)
/// wrapped in a CutTissueModel with cutter.lumpedMass().
/// @throws std::invalid_argument as makeTissueModel().
std::unique_ptr<TissueModel> makeCutTissueModel(ModelKind kind, const TetCutter& cutter,
                                                const Material& material);

}  // namespace surgical_sim::core
