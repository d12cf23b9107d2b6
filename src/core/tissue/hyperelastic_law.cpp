#include "surgical_sim/core/tissue/hyperelastic_law.h"

namespace surgical_sim::core {

Matrix9d HyperelasticLaw::tangent(const Eigen::Matrix3d& F, TangentMode mode) const {
  return mode == TangentMode::Exact ? firstPiolaDerivative(F) : projectedFirstPiolaDerivative(F);
}

StressAndTangent HyperelasticLaw::stressAndTangent(const Eigen::Matrix3d& F,
                                                   TangentMode mode) const {
  return {firstPiola(F), tangent(F, mode)};
}

std::optional<RotatedLinearStressAndTangent> HyperelasticLaw::rotatedLinearStressAndTangent(
    const Eigen::Matrix3d&) const {
  return std::nullopt;
}

}  // namespace surgical_sim::core
