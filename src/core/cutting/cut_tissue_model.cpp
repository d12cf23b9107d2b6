#include "surgical_sim/core/cutting/cut_tissue_model.h"

#include <stdexcept>
#include <string>

#include "surgical_sim/core/cutting/tet_cutter.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::core {

CutTissueModel::CutTissueModel(std::unique_ptr<TissueModel> elastic, Eigen::VectorXd lumped_mass)
    : elastic_(std::move(elastic)), mass_(std::move(lumped_mass)) {
  if (!elastic_) throw std::invalid_argument("CutTissueModel: elastic model is null");
  if (mass_.size() != elastic_->restPositions().size())
    throw std::invalid_argument(
        "CutTissueModel: lumped_mass has size " + std::to_string(mass_.size()) +
        ", expected 3 n = " + std::to_string(elastic_->restPositions().size()));
  if (!(mass_.array() > 0.0).all())
    throw std::invalid_argument("CutTissueModel: lumped_mass must be > 0 kg everywhere");
}

Eigen::VectorXd CutTissueModel::bodyForce(const Eigen::Vector3d& a) const {
  Eigen::VectorXd f(mass_.size());
  for (Eigen::Index i = 0; i < mass_.size() / 3; ++i)
    f.segment<3>(3 * i) = mass_.segment<3>(3 * i).cwiseProduct(a);
  return f;
}

std::unique_ptr<TissueModel> makeCutTissueModel(ModelKind kind, const TetCutter& cutter,
                                                const Material& material) {
  return std::make_unique<CutTissueModel>(makeTissueModel(kind, cutter.mesh(), material),
                                          cutter.lumpedMass());
}

}  // namespace surgical_sim::core
