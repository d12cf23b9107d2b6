// urdf/active_trocar.urdf against TrocarKinematics: (1) a chain of 4x4 transforms built from the
// TrocarGeometry numbers, (2) the chain read from the URDF's joint elements (a minimal string-level
// reading of <joint> origin/axis/type, enough for this hand-written file).
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "surgical_sim/core/haptics/trocar_kinematics.h"

namespace surgical_sim::core {
namespace {

struct UrdfJoint {
  std::string type, parent, child;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  double lower = 0.0, upper = 0.0;
};

std::string attribute(const std::string& element, const std::string& name) {
  const std::size_t at = element.find(" " + name + "=\"");
  if (at == std::string::npos) return "";
  const std::size_t begin = at + name.size() + 3;
  return element.substr(begin, element.find('"', begin) - begin);
}

/// The first <tag .../> element inside block, or "".
std::string element(const std::string& block, const std::string& tag) {
  const std::size_t at = block.find("<" + tag + " ");
  if (at == std::string::npos) return "";
  return block.substr(at, block.find('>', at) - at);
}

Eigen::Vector3d vector3(const std::string& text) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  std::istringstream in(text);
  in >> v.x() >> v.y() >> v.z();
  return v;
}

std::map<std::string, UrdfJoint> readJoints(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  const std::string urdf = text.str();
  std::map<std::string, UrdfJoint> joints;
  for (std::size_t at = urdf.find("<joint "); at != std::string::npos;
       at = urdf.find("<joint ", at + 1)) {
    const std::string block = urdf.substr(at, urdf.find("</joint>", at) - at);
    UrdfJoint j;
    j.type = attribute(block.substr(0, block.find('>')), "type");
    j.parent = attribute(element(block, "parent"), "link");
    j.child = attribute(element(block, "child"), "link");
    j.xyz = vector3(attribute(element(block, "origin"), "xyz"));
    j.rpy = vector3(attribute(element(block, "origin"), "rpy"));
    if (!element(block, "axis").empty()) j.axis = vector3(attribute(element(block, "axis"), "xyz"));
    const std::string limit = element(block, "limit");
    if (!attribute(limit, "lower").empty()) j.lower = std::stod(attribute(limit, "lower"));
    if (!attribute(limit, "upper").empty()) j.upper = std::stod(attribute(limit, "upper"));
    joints[attribute(block.substr(0, block.find('>')), "name")] = j;
  }
  return joints;
}

Eigen::Matrix4d translation(const Eigen::Vector3d& t) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<3, 1>(0, 3) = t;
  return T;
}

Eigen::Matrix4d rotation(const Eigen::Vector3d& axis, double angle) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<3, 3>(0, 0) = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  return T;
}

/// Pose of `link` in `root` following URDF semantics: origin (xyz, rpy = fixed-axis roll, pitch,
/// yaw) then the joint motion about/along the axis expressed in the joint frame.
Eigen::Matrix4d urdfChain(const std::map<std::string, UrdfJoint>& joints, const std::string& root,
                          std::string link, const std::map<std::string, double>& positions) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  while (link != root) {
    auto it = joints.begin();
    while (it != joints.end() && it->second.child != link) ++it;
    if (it == joints.end()) {
      ADD_FAILURE() << "no joint has child link " << link;
      return T;
    }
    const UrdfJoint& j = it->second;
    Eigen::Matrix4d origin = translation(j.xyz);
    origin.block<3, 3>(0, 0) = (Eigen::AngleAxisd(j.rpy.z(), Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(j.rpy.y(), Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(j.rpy.x(), Eigen::Vector3d::UnitX()))
                                   .toRotationMatrix();
    const auto q = positions.find(it->first);
    const double value = q == positions.end() ? 0.0 : q->second;
    Eigen::Matrix4d motion = Eigen::Matrix4d::Identity();
    if (j.type == "revolute" || j.type == "continuous") motion = rotation(j.axis, value);
    if (j.type == "prismatic") motion = translation(value * j.axis);
    T = origin * motion * T;
    link = j.parent;
  }
  return T;
}

const char* const kJointNames[kTrocarJointCount] = {"trocar_pitch", "trocar_yaw", "trocar_spin",
                                                    "trocar_insertion", "trocar_grip"};

TEST(TrocarUrdf, ChainFromGeometryNumbersEqualsKinematics) {
  const TrocarGeometry g = TrocarGeometry::chendebPrototype();
  const TrocarKinematics kin(g);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    TrocarJointVector q;
    q << 1.2 * u(rng), 1.2 * u(rng), M_PI * u(rng), 0.15 * (1.0 + u(rng)), 0.5 * (1.0 + u(rng));
    const Eigen::Matrix4d chain = rotation(Eigen::Vector3d::UnitX(), q[kTrocarPitch]) *
                                  rotation(Eigen::Vector3d::UnitY(), q[kTrocarYaw]) *
                                  rotation(Eigen::Vector3d::UnitZ(), q[kTrocarSpin]) *
                                  translation(Eigen::Vector3d(0, 0, q[kTrocarInsertion])) *
                                  translation(Eigen::Vector3d(0, 0, g.tip_offset));
    EXPECT_LT((chain - kin.toolTipPose(q).matrix()).cwiseAbs().maxCoeff(), 1e-14);
  }
}

TEST(TrocarUrdf, UrdfFileChainEqualsKinematicsAndLimitsMatchTheDevice) {
  const auto joints = readJoints(std::string(SURGICAL_SIM_SOURCE_DIR) + "/urdf/active_trocar.urdf");
  for (const char* name : kJointNames) ASSERT_EQ(joints.count(name), 1u) << name;
  EXPECT_EQ(joints.at("trocar_pitch").type, "revolute");
  EXPECT_EQ(joints.at("trocar_yaw").type, "revolute");
  EXPECT_EQ(joints.at("trocar_spin").type, "continuous");
  EXPECT_EQ(joints.at("trocar_insertion").type, "prismatic");
  EXPECT_EQ(joints.at("trocar_grip").type, "revolute");
  EXPECT_NEAR(joints.at("trocar_pitch").upper, M_PI / 4, 1e-10);
  EXPECT_NEAR(joints.at("trocar_yaw").lower, -M_PI / 4, 1e-10);
  EXPECT_NEAR(joints.at("trocar_insertion").upper, 0.30, 1e-12);
  EXPECT_NEAR(joints.at("trocar_grip").upper, M_PI / 3, 1e-10);

  const TrocarKinematics kin(TrocarGeometry::chendebPrototype());
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    TrocarJointVector q;
    q << 0.78 * u(rng), 0.78 * u(rng), M_PI * u(rng), 0.15 * (1.0 + u(rng)), 0.5 * (1.0 + u(rng));
    std::map<std::string, double> positions;
    for (int j = 0; j < kTrocarJointCount; ++j) positions[kJointNames[j]] = q[j];
    const Eigen::Matrix4d urdf = urdfChain(joints, "trocar", "tool_tip", positions);
    EXPECT_LT((urdf - kin.toolTipPose(q).matrix()).cwiseAbs().maxCoeff(), 1e-14);
  }
}

}  // namespace
}  // namespace surgical_sim::core
