#include "surgical_sim/core/haptics/trocar_chain.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/haptics/trocar_joints.h"

namespace surgical_sim::core {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void requireRigid(const std::string& name, const Eigen::Isometry3d& X) {
  const Eigen::Matrix3d R = X.linear();
  if (!X.matrix().allFinite() || !(R.transpose() * R).isApprox(Eigen::Matrix3d::Identity(), 1e-9) ||
      R.determinant() < 0.0)
    throw std::invalid_argument(name +
                                " is out of range: must be a finite rigid transform (rotation "
                                "orthonormal, det +1)");
}

TrocarJointType expectedType(int joint) {
  switch (joint) {
    case kTrocarSpin:
      return TrocarJointType::Continuous;
    case kTrocarInsertion:
      return TrocarJointType::Prismatic;
    default:
      return TrocarJointType::Revolute;
  }
}

}  // namespace

TrocarChain::TrocarChain() {
  for (TrocarChainJoint& joint : joints) {
    joint.X_PJ.matrix().setConstant(kNaN);
    joint.axis.setConstant(kNaN);
  }
  X_JT.matrix().setConstant(kNaN);
}

void validateTrocarChain(const TrocarChain& chain) {
  static_assert(kTrocarChainJointCount == kTrocarGrip, "the chain ends before the grip joint");
  for (int j = 0; j < kTrocarChainJointCount; ++j) {
    const TrocarChainJoint& joint = chain.joints[static_cast<std::size_t>(j)];
    const std::string prefix = std::string("trocar.chain.") + trocarJointName(j);
    if (joint.type != expectedType(j))
      throw std::invalid_argument(prefix +
                                  ".type is out of range: pitch and yaw must be revolute, spin "
                                  "continuous, insertion prismatic");
    requireRigid(prefix + ".X_PJ", joint.X_PJ);
    if (!joint.axis.allFinite() || std::abs(joint.axis.norm() - 1.0) > 1e-9)
      throw std::invalid_argument(prefix + ".axis is out of range: must be a finite unit vector");
  }
  requireRigid("trocar.chain.X_JT", chain.X_JT);
}

}  // namespace surgical_sim::core
