// MultiBodySimulation: organs coupled by connective layers, grasped, pulled and pushed by tools.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "surgical_sim/core/contact/closest_point_on_segment.h"
#include "surgical_sim/core/scene/multi_body_simulation.h"
#include "surgical_sim/core/scene/scene_config.h"

namespace surgical_sim::core {
namespace {

std::string sceneText(const std::string& file) {
  std::ifstream in(std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/scenes/" + file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Replaces every occurrence of `from` in `text` by `to` (at least one).
std::string replacedAll(std::string text, const std::string& from, const std::string& to) {
  std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  for (; at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

/// Scene (b) (config/scenes/connective_two_organs.yaml) coarser, for speed: organ meshes of
/// 4 x 4 x 4 cells (nodes every 10 mm across the grasped face), a layer with rigid nodes every
/// 8 mm and samples every 5 mm, jaws of 12 mm (5 nodes grasped).
RuntimeScene twoOrgans() {
  std::string text = sceneText("connective_two_organs.yaml");
  text = replacedAll(text, "resolution: [9, 6, 6]", "resolution: [4, 4, 4]");
  text = replacedAll(text, "node_spacing: 0.0057", "node_spacing: 0.008");
  text = replacedAll(text, "sample_spacing: 0.0034", "sample_spacing: 0.005");
  text = replacedAll(text, "grasp: {radius: 0.008", "grasp: {radius: 0.012");
  return parseRuntimeScene(text, "connective_two_organs.yaml");
}

/// The grasper's tip at (x, 2 cm, 2 cm), its z axis (into the tissue) along +x.
Eigen::Isometry3d tipAt(double x) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  X.translation() = Eigen::Vector3d(x, 0.02, 0.02);
  return X;
}

/// Mean displacement [m] of the attached nodes of body b.
Eigen::Vector3d attachedDisplacement(const MultiBodySimulation& sim, int b) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (int a = 0; a < sim.bodyMesh(b).numNodes(); ++a) {
    if (!sim.coupling().attached(b, a)) continue;
    sum += sim.bodyPositions(b).segment<3>(3 * a) - sim.bodyMesh(b).nodes.col(a);
    ++count;
  }
  return sum / count;
}

/// Largest node displacement [m] of every body from rest.
double largestDisplacement(const MultiBodySimulation& sim) {
  double largest = 0.0;
  for (int b = 0; b < sim.numBodies(); ++b)
    for (int a = 0; a < sim.bodyMesh(b).numNodes(); ++a)
      largest = std::max(
          largest, (sim.bodyPositions(b).segment<3>(3 * a) - sim.bodyMesh(b).nodes.col(a)).norm());
  return largest;
}

/// Grasps the near organ's far face at its centre and pulls it 1 cm away from the far organ
/// (tip ramped over 20 steps, held 10 more); returns the step statuses' worst (Ok expected).
void graspAndPull(MultiBodySimulation& sim) {
  sim.setToolPose(0, tipAt(-0.001));
  sim.setGrasp(0, true);
  for (int i = 0; i < 30; ++i) {
    sim.setToolPose(0, tipAt(-0.001 - 0.01 * std::min(1.0, (i + 1) / 20.0)));
    ASSERT_EQ(sim.step().report.status, StepStatus::Ok) << "pull step " << i;
  }
}

TEST(MultiBodySimulation, GraspAndPullDragsTheOtherOrganAndReleaseReturnsBothToRest) {
  MultiBodySimulation sim(twoOrgans());
  const RigidNodeModel& layer = sim.layer(0);
  std::printf("two organs: %d + %d tets, layer %d rigid nodes, %d samples, %d unknowns\n",
              sim.bodyMesh(0).numElements(), sim.bodyMesh(1).numElements(), layer.numNodes(),
              layer.numSamples(), sim.coupling().numUnknowns());
  graspAndPull(sim);
  const ContactLinearization pulled = sim.toolContact(0);
  const Eigen::Vector3d near = attachedDisplacement(sim, 0);
  const Eigen::Vector3d far = attachedDisplacement(sim, 1);
  std::printf(
      "pulled 10 mm along -x: grasp force %.3f N (%d springs), near organ's attached "
      "nodes %.3e m, far organ's %.3e m along -x\n",
      pulled.f0_S.x(), pulled.contacts, -near.x(), -far.x());
  // The tissue pulls the tool back towards +x; the grasp is implicit, K_S = -k I per node.
  EXPECT_TRUE(pulled.in_contact);
  EXPECT_EQ(pulled.contacts, 5);
  EXPECT_GT(pulled.f0_S.x(), 0.1);
  EXPECT_NEAR(pulled.K_S(0, 0), -5 * 2e3, 1e-9);
  // Both organs follow the pull: the far organ (held at its far face) through the layer.
  EXPECT_LT(near.x(), -2e-3);
  EXPECT_LT(far.x(), -0.5e-3);
  EXPECT_GT(-far.x(), 2.0 * std::abs(far.z()));

  // Release and take the tool away: both organs return to rest, the tool force to zero.
  sim.setGrasp(0, false);
  sim.setToolPose(0, tipAt(-0.05));
  double largest = 0.0;
  int step = 0;
  for (; step < 200; ++step) {
    ASSERT_EQ(sim.step().report.status, StepStatus::Ok) << "release step " << step;
    largest = largestDisplacement(sim);
    if (largest < 1e-5) break;
  }
  std::printf("released: largest displacement %.3e m after %d steps\n", largest, step + 1);
  EXPECT_LT(largest, 1e-5);  // 1e-3 of the pull
  EXPECT_FALSE(sim.toolContact(0).in_contact);
  EXPECT_EQ(sim.toolContact(0).f0_S, Eigen::Vector3d::Zero());
}

TEST(MultiBodySimulation, ToolContactPushesBothOrgansWithoutPassingThrough) {
  MultiBodySimulation sim(twoOrgans());
  const ToolSpec& tool = sim.scene().tools[0];
  // Push the tip 6 mm into the near organ's far face (x = 0) at its centre, over 12 steps.
  for (int i = 0; i < 20; ++i) {
    sim.setToolPose(0, tipAt(-tool.radius + 0.006 * std::min(1.0, (i + 1) / 12.0)));
    ASSERT_EQ(sim.step().report.status, StepStatus::Ok) << "push step " << i;
  }
  // Every surface node of both organs is outside the capsule but for a fraction of a millimetre
  // (the penalty springs' give and the step's lag).
  const Eigen::Isometry3d X = tipAt(-tool.radius + 0.006);
  const Eigen::Vector3d end = X.translation() - tool.shaft_length * X.linear().col(2);
  double deepest = 0.0;
  for (int b = 0; b < sim.numBodies(); ++b)
    for (const int a : sim.bodySurface(b).nodes) {
      const double d = std::sqrt(
          closestPointOnSegment(X.translation(), end, sim.bodyPositions(b).segment<3>(3 * a))
              .distance_squared);
      deepest = std::max(deepest, tool.radius - d);
    }
  const ContactLinearization c = sim.toolContact(0);
  const Eigen::Vector3d near = attachedDisplacement(sim, 0);
  const Eigen::Vector3d far = attachedDisplacement(sim, 1);
  std::printf(
      "pushed 6 mm: deepest node %.3e m inside the capsule, force %.3f N (%d contacts), "
      "attached nodes moved %.3e / %.3e m along +x\n",
      deepest, c.f0_S.x(), c.contacts, near.x(), far.x());
  EXPECT_LT(deepest, 0.5e-3);
  EXPECT_TRUE(c.in_contact);
  EXPECT_LT(c.f0_S.x(), -0.05);  // the tissue pushes the tool back (-x)
  EXPECT_LT(c.K_S(0, 0), 0.0);
  EXPECT_GT(near.x(), 0.5e-3);
  EXPECT_GT(far.x(), 0.0);
  EXPECT_FALSE(sim.contactNodes()[0].empty());
}

TEST(MultiBodySimulation, BadPosesAreRejectedWithTheStateUnchangedAndResetReplaysBitIdentically) {
  MultiBodySimulation sim(twoOrgans());
  graspAndPull(sim);
  const CoupledState before = sim.state();
  const ContactLinearization contact = sim.toolContact(0);
  Eigen::Isometry3d nan = tipAt(-0.011);
  nan.translation().x() = std::numeric_limits<double>::quiet_NaN();
  Eigen::Isometry3d sheared = tipAt(-0.011);
  sheared.linear()(0, 1) = 0.5;
  for (const Eigen::Isometry3d& bad : {nan, sheared, tipAt(2e3)})
    EXPECT_THROW(sim.setToolPose(0, bad), std::invalid_argument);
  EXPECT_THROW(sim.setToolPose(1, tipAt(0.0)), std::invalid_argument);
  for (std::size_t o = 0; o < before.organ_positions.size(); ++o)
    EXPECT_EQ(sim.state().organ_positions[o], before.organ_positions[o]);
  EXPECT_EQ(sim.toolContact(0).f0_S, contact.f0_S);
  // The tool stays where it was: the next step is a hold, not a jump.
  ASSERT_EQ(sim.step().report.status, StepStatus::Ok);
  EXPECT_LT((sim.state().organ_positions[0] - before.organ_positions[0]).cwiseAbs().maxCoeff(),
            1e-3);

  // Replay after reset: bit-identical.
  const CoupledState first = sim.state();
  sim.reset();
  const MultiBodySimulation fresh(twoOrgans());
  for (std::size_t o = 0; o < first.organ_positions.size(); ++o)
    EXPECT_EQ(sim.state().organ_positions[o], fresh.state().organ_positions[o]);
  EXPECT_FALSE(sim.toolContact(0).in_contact);
  graspAndPull(sim);
  ASSERT_EQ(sim.step().report.status, StepStatus::Ok);
  for (std::size_t o = 0; o < first.organ_positions.size(); ++o)
    EXPECT_EQ(sim.state().organ_positions[o], first.organ_positions[o]);
  EXPECT_EQ(sim.state().time, first.time);
}

TEST(MultiBodySimulation, GraspAboveMaxForceSlipsAndContactForceIsCapped) {
  RuntimeScene scene = twoOrgans();
  scene.tools[0].max_force = 0.05;
  MultiBodySimulation sim(scene);
  sim.setToolPose(0, tipAt(-0.001));
  sim.setGrasp(0, true);
  StepStatus worst = StepStatus::Ok;
  for (int i = 0; i < 10; ++i) {
    sim.setToolPose(0, tipAt(-0.001 - 0.002 * (i + 1)));
    const StepStatus status = sim.step().report.status;
    if (status != StepStatus::Ok) worst = status;
  }
  EXPECT_EQ(worst, StepStatus::ContactLimited);
  EXPECT_FALSE(sim.toolContact(0).in_contact);  // the jaws let go

  // Pushing deep against a 0.05 N cap: ContactLimited, the push bounded near the cap.
  sim.reset();
  StepStatus last = StepStatus::Ok;
  for (int i = 0; i < 10; ++i) {
    sim.setToolPose(0, tipAt(0.001 * (i + 1)));
    last = sim.step().report.status;
  }
  EXPECT_EQ(last, StepStatus::ContactLimited);
  EXPECT_LT(sim.toolContact(0).f0_S.norm(), 2 * scene.tools[0].max_force);
}

TEST(MultiBodySimulation, StackedPlatesSagOneBelowTheOtherUnderGravity) {
  // Coarser than the shipped scene (4 x 4 cells per plate and layer), for speed.
  MultiBodySimulation sim(
      parseRuntimeScene(replacedAll(sceneText("connective_plates.yaml"), "resolution: [6, 6, 1]",
                                    "resolution: [4, 4, 1]"),
                        "connective_plates.yaml"));
  ASSERT_EQ(sim.numBodies(), 3);
  for (int i = 0; i < 30; ++i) ASSERT_EQ(sim.step().report.status, StepStatus::Ok) << i;
  std::vector<double> sag;
  for (int b = 0; b < 3; ++b) {
    double sum = 0.0;
    const int n = sim.bodyMesh(b).numNodes();
    for (int a = 0; a < n; ++a)
      sum += sim.bodyMesh(b).nodes(2, a) - sim.bodyPositions(b)[3 * a + 2];
    sag.push_back(sum / n);
  }
  std::printf("plates: mean sag %.3e / %.3e / %.3e m\n", sag[0], sag[1], sag[2]);
  EXPECT_GT(sag[0], 0.0);
  EXPECT_GT(sag[1], sag[0]);
  EXPECT_GT(sag[2], sag[1]);
  // The layer surfaces follow their rigid nodes: the lower layer's sank with the plates.
  const Eigen::Matrix3Xd layer = sim.layerSurfacePositions(1);
  EXPECT_LT((layer - sim.layerSurface(1).rest).row(2).mean(), -0.5 * sag[1]);
}

}  // namespace
}  // namespace surgical_sim::core
