// The trocar model read from its URDF (readTrocarUrdf) against the URDF itself, walked generically
// through urdfdom's model: forward kinematics, limits that decide the clamping, and the errors of
// broken URDFs.
#include "surgical_sim/core/haptics/trocar_urdf.h"

#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "../common/urdf_link_pose.h"
#include "shipped_trocar.h"
#include "surgical_sim/core/haptics/trocar_device.h"
#include "surgical_sim/core/haptics/trocar_kinematics.h"

namespace surgical_sim::core {
namespace {

/// text with the first occurrence of `from` after `<joint name="joint"` replaced by `to`.
std::string inJoint(std::string text, const std::string& joint, const std::string& from,
                    const std::string& to) {
  const std::size_t at = text.find("<joint name=\"" + joint + "\"");
  const std::size_t hit = at == std::string::npos ? at : text.find(from, at);
  if (hit == std::string::npos) {
    ADD_FAILURE() << "'" << from << "' not found in joint " << joint;
    return text;
  }
  return text.replace(hit, from.size(), to);
}

/// The shipped URDF with every name prefixed for trocar `name` (all its names start with
/// "trocar"), placed in `world` by a fixed joint at xyz/rpy.
std::string prefixedCopy(const std::string& name, const std::string& xyz, const std::string& rpy) {
  std::string text = shippedTrocarUrdfText();
  for (std::size_t at = text.find("\"trocar"); at != std::string::npos;
       at = text.find("\"trocar", at + 1))
    text.replace(at + 1, 6, name);
  const std::string mount = "<link name=\"world\"/><joint name=\"world_to_" + name +
                            "\" type=\"fixed\"><parent link=\"world\"/><child link=\"" + name +
                            "\"/><origin xyz=\"" + xyz + "\" rpy=\"" + rpy + "\"/></joint>";
  return text.replace(text.find("</robot>"), 0, mount);
}

std::string errorOf(const std::string& urdf_text) {
  try {
    readTrocarUrdf(urdf_text, TrocarUrdfNames::forTrocar("trocar"));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

const char* const kSuffixes[kTrocarJointCount] = {"pitch", "yaw", "spin", "insertion", "grip"};

/// Model FK (placed at X_WF) equals the URDF chain from `root` to <name>_tool_tip, random joints.
void expectModelEqualsUrdfChain(const std::string& text, const std::string& name,
                                const std::string& root, const Eigen::Isometry3d& X_WF) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text);
  ASSERT_TRUE(model);
  const TrocarUrdf trocar = readTrocarUrdf(text, TrocarUrdfNames::forTrocar(name));
  const TrocarKinematics kin(trocar.chain);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    TrocarJointVector q;
    q << 1.2 * u(rng), 1.2 * u(rng), M_PI * u(rng), 0.15 * (1.0 + u(rng)), 0.5 * (1.0 + u(rng));
    std::map<std::string, double> positions;
    for (int j = 0; j < kTrocarJointCount; ++j) positions[name + "_" + kSuffixes[j]] = q[j];
    const Eigen::Isometry3d urdf = test::urdfLinkPose(*model, root, name + "_tool_tip", positions);
    EXPECT_LT((urdf.matrix() - (X_WF * kin.toolTipPose(q)).matrix()).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(TrocarUrdf, ModelForwardKinematicsEqualsTheShippedUrdfChain) {
  const TrocarUrdf trocar = shippedTrocar();
  EXPECT_FALSE(trocar.X_WF.has_value());  // the shipped file does not place the trocar
  expectModelEqualsUrdfChain(shippedTrocarUrdfText(), "trocar", "trocar",
                             Eigen::Isometry3d::Identity());
}

TEST(TrocarUrdf, PrefixedCopyInWorldGivesTheSameModelAtItsFulcrum) {
  const std::string text = prefixedCopy("trocar_2", "0.1 -0.05 0.2", "3.0 0.2 -0.4");
  const TrocarUrdf trocar = readTrocarUrdf(text, TrocarUrdfNames::forTrocar("trocar_2"));
  ASSERT_TRUE(trocar.X_WF.has_value());
  const Eigen::Isometry3d X_WF = Eigen::Translation3d(0.1, -0.05, 0.2) *
                                 Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(3.0, Eigen::Vector3d::UnitX());
  EXPECT_LT((trocar.X_WF->matrix() - X_WF.matrix()).cwiseAbs().maxCoeff(), 1e-12);
  expectModelEqualsUrdfChain(text, "trocar_2", "world", X_WF);
  EXPECT_EQ(trocar.joints[kTrocarGrip].name, "trocar_2_grip");
}

TEST(TrocarUrdf, DeviceLimitsEffortsAndFrictionComeFromTheUrdf) {
  const TrocarDeviceConfig c = shippedDeviceConfig();
  EXPECT_DOUBLE_EQ(c.pitch_limit, M_PI / 4);
  EXPECT_DOUBLE_EQ(c.yaw_limit, M_PI / 4);
  EXPECT_DOUBLE_EQ(c.insertion_max, 0.30);
  EXPECT_DOUBLE_EQ(c.grip_max, M_PI / 3);
  const double effort[kTrocarJointCount] = {6.0, 6.0, 0.2, 5.0, 0.3};
  const double damping[kTrocarJointCount] = {0.005, 0.005, 0.0005, 0.2, 0.0001};
  for (int j = 0; j < kTrocarJointCount; ++j) {
    EXPECT_EQ(c.drives[j].effort_limit, effort[j]) << kSuffixes[j];
    EXPECT_EQ(c.drives[j].viscous_friction, damping[j]) << kSuffixes[j];
  }
  // One edit of the effort limit in the text changes the saturation.
  const std::string text =
      inJoint(shippedTrocarUrdfText(), "trocar_insertion", "effort=\"5.0\"", "effort=\"2.5\"");
  const TrocarDevice device(makeTrocarDeviceConfig(
      readTrocarUrdf(text, TrocarUrdfNames::forTrocar("trocar")), chendebPrototypeMotors()));
  TrocarJointVector tau = TrocarJointVector::Zero();
  tau[kTrocarInsertion] = 4.0;
  EXPECT_TRUE(device.saturate(tau).saturated);
  EXPECT_DOUBLE_EQ(tau[kTrocarInsertion], 2.5);
}

TEST(TrocarUrdf, ChangingAJointLimitInTheUrdfChangesTheClamping) {
  TrocarJointVector q;
  q << 0.7, -0.7, 0.0, 0.28, 0.9;
  TrocarJointVector shipped = q;
  EXPECT_FALSE(TrocarDevice(shippedDeviceConfig()).clampToLimits(shipped));

  std::string text = shippedTrocarUrdfText();
  text = inJoint(text, "trocar_pitch", "lower=\"-0.7853981633974483\" upper=\"0.7853981633974483\"",
                 "lower=\"-0.5\" upper=\"0.5\"");
  text = inJoint(text, "trocar_insertion", "upper=\"0.30\"", "upper=\"0.25\"");
  const TrocarDevice device(makeTrocarDeviceConfig(
      readTrocarUrdf(text, TrocarUrdfNames::forTrocar("trocar")), chendebPrototypeMotors()));
  TrocarJointVector clamped = q;
  EXPECT_TRUE(device.clampToLimits(clamped));
  EXPECT_EQ(clamped[kTrocarPitch], 0.5);
  EXPECT_EQ(clamped[kTrocarYaw], -0.7);  // yaw keeps its +-45 deg
  EXPECT_EQ(clamped[kTrocarInsertion], 0.25);
  EXPECT_EQ(clamped[kTrocarGrip], 0.9);
}

TEST(TrocarUrdf, BrokenUrdfsGiveErrorsNamingTheProblem) {
  const std::string text = shippedTrocarUrdfText();
  const auto expectError = [](const std::string& broken, const std::string& expected) {
    const std::string error = errorOf(broken);
    EXPECT_NE(error.find(expected), std::string::npos) << "got: '" << error << "'";
  };
  expectError("<robot", "urdfdom cannot parse it");
  expectError(inJoint(text, "trocar_yaw", "name=\"trocar_yaw\"", "name=\"trocar_yaw2\""),
              "trocar URDF has no joint 'trocar_yaw'");
  std::string renamed_tip = text;
  for (std::size_t at; (at = renamed_tip.find("\"trocar_tool_tip\"")) != std::string::npos;)
    renamed_tip.replace(at, 17, "\"trocar_tip\"");
  expectError(renamed_tip, "has no link 'trocar_tool_tip'");
  struct Edit {
    const char *joint, *from, *to, *error;
  };
  const Edit edits[] = {
      {"trocar_insertion", "type=\"prismatic\"", "type=\"revolute\"",
       "joint 'trocar_insertion' is revolute: must be prismatic"},
      {"trocar_yaw", "<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0 0 0\"/>",
       "joint 'trocar_yaw' has a zero <axis>"},
      {"trocar_pitch", "upper=\"0.7853981633974483\"", "upper=\"1.4\"",
       "joint 'trocar_pitch' <limit upper> = 1.4 rad is out of range"},
      {"trocar_yaw", "lower=\"-0.7853981633974483\"", "lower=\"-0.5\"",
       "joint 'trocar_yaw' <limit lower> = -0.5"},
      {"trocar_insertion", "upper=\"0.30\"", "upper=\"0.4\"",
       "joint 'trocar_insertion' <limit upper> = 0.4 m is out of range"},
      {"trocar_grip", "effort=\"0.3\"", "effort=\"0\"",
       "joint 'trocar_grip' <limit effort> = 0 N m is out of range"},
      {"trocar_spin", "<dynamics damping=\"0.0005\" friction=\"0.002\"/>", "",
       "joint 'trocar_spin' has no <dynamics"},
      {"trocar_shaft_mount", "type=\"fixed\"", "type=\"continuous\"",
       "joint 'trocar_shaft_mount' (continuous) lies between 'trocar' and 'trocar_tool_tip'"},
  };
  for (const Edit& edit : edits)
    expectError(inJoint(text, edit.joint, edit.from, edit.to), edit.error);
  std::string on_table = text;
  on_table.replace(on_table.find("</robot>"), 0,
                   "<link name=\"table\"/><joint name=\"table_to_trocar\" type=\"fixed\"><parent "
                   "link=\"table\"/><child link=\"trocar\"/></joint>");
  expectError(on_table, "hangs from link 'table' by fixed joint 'table_to_trocar'");
  EXPECT_EQ(errorOf(text), "");
}

}  // namespace
}  // namespace surgical_sim::core
