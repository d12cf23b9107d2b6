#include "surgical_sim/core/haptics/trocar_urdf.h"

#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

Eigen::Isometry3d toIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  X.linear() =
      Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
          .normalized()
          .toRotationMatrix();
  return X;
}

const char* typeName(int type) {
  // Indexed by urdf::Joint's enum: UNKNOWN, REVOLUTE, CONTINUOUS, PRISMATIC, FLOATING, PLANAR,
  // FIXED.
  static constexpr const char* kNames[] = {"unknown",  "revolute", "continuous", "prismatic",
                                           "floating", "planar",   "fixed"};
  return type >= 0 && type < 7 ? kNames[type] : "unknown";
}

int expectedUrdfType(int joint) {
  if (joint == kTrocarSpin) return urdf::Joint::CONTINUOUS;
  if (joint == kTrocarInsertion) return urdf::Joint::PRISMATIC;
  return urdf::Joint::REVOLUTE;
}

TrocarJointType toTrocarJointType(int urdf_type) {
  if (urdf_type == urdf::Joint::CONTINUOUS) return TrocarJointType::Continuous;
  if (urdf_type == urdf::Joint::PRISMATIC) return TrocarJointType::Prismatic;
  return TrocarJointType::Revolute;
}

/// Limits and dynamics of joint `j`, checked against the ranges of validateTrocarDeviceConfig.
TrocarUrdfJoint readJointLimits(const urdf::Joint& joint, int j) {
  const std::string where = "trocar URDF joint '" + joint.name + "' ";
  if (!joint.limits)
    throw std::invalid_argument(where + "has no <limit>: the device needs its effort limit");
  if (!joint.dynamics)
    throw std::invalid_argument(where +
                                "has no <dynamics damping=.. friction=..>: the device needs its "
                                "joint friction");
  const bool prismatic = j == kTrocarInsertion;
  TrocarUrdfJoint out;
  out.name = joint.name;
  out.effort = joint.limits->effort;
  out.damping = joint.dynamics->damping;
  out.friction = joint.dynamics->friction;
  requirePositive(where + "<limit effort>", out.effort, prismatic ? "N" : "N m");
  requireNonNegative(where + "<dynamics damping>", out.damping, prismatic ? "N s/m" : "N m s/rad");
  requireNonNegative(where + "<dynamics friction>", out.friction, prismatic ? "N" : "N m");
  if (j == kTrocarSpin) return out;  // continuous: no position limits
  out.lower = joint.limits->lower;
  out.upper = joint.limits->upper;
  if (j == kTrocarPitch || j == kTrocarYaw) {
    requireInRange(where + "<limit upper>", out.upper, 0.0, kTrocarMaxTiltLimitDeg * kDegToRad,
                   "rad");
    if (std::abs(out.lower + out.upper) > 1e-12)
      throw std::invalid_argument(where + "<limit lower> = " + std::to_string(out.lower) +
                                  " rad is out of range: the device's " + trocarJointName(j) +
                                  " range is symmetric, lower must equal -upper (" +
                                  std::to_string(-out.upper) + " rad)");
    return out;
  }
  requireInRange(where + "<limit lower>", out.lower, 0.0, 0.0, prismatic ? "m" : "rad");
  if (prismatic)
    requireInRange(where + "<limit upper>", out.upper, 1e-9, kTrocarMaxInsertion, "m");
  else
    requireInRange(where + "<limit upper>", out.upper, 1e-9, kTrocarMaxGripDeg * kDegToRad, "rad");
  return out;
}

}  // namespace

TrocarUrdfNames TrocarUrdfNames::forTrocar(const std::string& name) {
  TrocarUrdfNames names;
  names.base_link = name;
  names.joint_prefix = name + "_";
  return names;
}

TrocarUrdf readTrocarUrdf(const std::string& urdf_xml, const TrocarUrdfNames& names) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf_xml);
  if (!model)
    throw std::invalid_argument(
        "trocar URDF is not valid URDF: urdfdom cannot parse it (its reason is printed above)");
  const std::string tip_name = names.joint_prefix + "tool_tip";
  const urdf::LinkConstSharedPtr base = model->getLink(names.base_link);
  const urdf::LinkConstSharedPtr tip = model->getLink(tip_name);
  if (!base || !tip)
    throw std::invalid_argument("trocar URDF has no link '" + (base ? tip_name : names.base_link) +
                                "' (trocar base link '" + names.base_link + "', tip link '" +
                                tip_name + "')");

  TrocarUrdf out;
  std::array<urdf::JointConstSharedPtr, kTrocarJointCount> joints;
  for (int j = 0; j < kTrocarJointCount; ++j) {
    const std::string name = names.joint_prefix + trocarJointName(j);
    joints[j] = model->getJoint(name);
    if (!joints[j]) throw std::invalid_argument("trocar URDF has no joint '" + name + "'");
    if (joints[j]->type != expectedUrdfType(j))
      throw std::invalid_argument("trocar URDF joint '" + name + "' is " +
                                  typeName(joints[j]->type) + ": must be " +
                                  typeName(expectedUrdfType(j)));
    const urdf::Vector3& a = joints[j]->axis;
    const Eigen::Vector3d axis(a.x, a.y, a.z);
    if (!(axis.norm() > 1e-12))
      throw std::invalid_argument("trocar URDF joint '" + name + "' has a zero <axis>");
    out.joints[j] = readJointLimits(*joints[j], j);
  }

  // Walk from the tip up to the base: fixed joints compose, the four chain joints in order.
  std::vector<urdf::JointConstSharedPtr> path;  // tip -> base
  for (urdf::LinkConstSharedPtr link = tip; link != base;) {
    if (!link->parent_joint)
      throw std::invalid_argument("trocar URDF: tip link '" + tip_name +
                                  "' does not hang below base link '" + names.base_link + "'");
    path.push_back(link->parent_joint);
    link = model->getLink(link->parent_joint->parent_link_name);
  }
  int next = 0;  // next chain joint expected, walking base -> tip
  Eigen::Isometry3d X_fixed = Eigen::Isometry3d::Identity();
  for (auto it = path.rbegin(); it != path.rend(); ++it) {
    const urdf::Joint& joint = **it;
    X_fixed = X_fixed * toIsometry(joint.parent_to_joint_origin_transform);
    if (joint.type == urdf::Joint::FIXED) continue;
    if (next == kTrocarChainJointCount || joint.name != joints[next]->name)
      throw std::invalid_argument(
          "trocar URDF joint '" + joint.name + "' (" + typeName(joint.type) + ") lies between '" +
          names.base_link + "' and '" + tip_name + "': the chain must be " + names.joint_prefix +
          "pitch, yaw, spin, insertion in this order, with only fixed joints between them");
    TrocarChainJoint& chain_joint = out.chain.joints[next];
    chain_joint.type = toTrocarJointType(joint.type);
    chain_joint.X_PJ = X_fixed;
    chain_joint.axis = Eigen::Vector3d(joint.axis.x, joint.axis.y, joint.axis.z).normalized();
    X_fixed = Eigen::Isometry3d::Identity();
    ++next;
  }
  if (next != kTrocarChainJointCount)
    throw std::invalid_argument("trocar URDF joint '" + joints[next]->name + "' is not between '" +
                                names.base_link + "' and '" + tip_name + "'");
  out.chain.X_JT = X_fixed;
  validateTrocarChain(out.chain);

  if (const urdf::JointConstSharedPtr mount = base->parent_joint) {
    if (mount->type != urdf::Joint::FIXED || mount->parent_link_name != names.world_link)
      throw std::invalid_argument(
          "trocar URDF: base link '" + names.base_link + "' hangs from link '" +
          mount->parent_link_name + "' by " + typeName(mount->type) + " joint '" + mount->name +
          "': a trocar base is a root link or fixed to '" + names.world_link + "'");
    out.X_WF = toIsometry(mount->parent_to_joint_origin_transform);
  }
  return out;
}

TrocarDeviceConfig makeTrocarDeviceConfig(const TrocarUrdf& urdf, const TrocarMotors& motors) {
  TrocarDeviceConfig config;
  for (int j = 0; j < kTrocarJointCount; ++j) {
    TrocarJointDrive& drive = config.drives[j];
    drive.gear_ratio = motors[j].gear_ratio;
    drive.rotor_inertia = motors[j].rotor_inertia;
    drive.encoder_step = motors[j].encoder_step;
    drive.effort_limit = urdf.joints[j].effort;
    drive.viscous_friction = urdf.joints[j].damping;
    drive.coulomb_friction = urdf.joints[j].friction;
  }
  config.pitch_limit = urdf.joints[kTrocarPitch].upper;
  config.yaw_limit = urdf.joints[kTrocarYaw].upper;
  config.insertion_max = urdf.joints[kTrocarInsertion].upper;
  config.grip_max = urdf.joints[kTrocarGrip].upper;
  validateTrocarDeviceConfig(config);
  return config;
}

}  // namespace surgical_sim::core
