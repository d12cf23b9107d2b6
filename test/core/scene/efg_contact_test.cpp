// Tool contact, grasp and the haptic contact model on a meshless EFG tissue through its surface
// mapping, against the tet4 / tet10 answers of the same block; tet scenes keep their surface
// positions bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace surgical_sim::core {
namespace {

// A 6 x 6 x 3 cm block clamped at its base, pressed at the centre of its top by a 5 mm tool.
std::string blockScene(const std::string& model, const std::string& element_type, int resolution) {
  const std::string r = std::to_string(resolution);
  return R"(
name: efg_block
mesh:
  generator: box
  origin: [-0.03, -0.03, 0.0]
  size: [0.06, 0.06, 0.03]
  resolution: [)" +
         r + ", " + r + ", " + std::to_string(resolution / 2) + R"(]
  element_type: )" +
         element_type + R"(
material: {young_modulus: 5.0e3, poisson_ratio: 0.45, density: 1000.0}
model: )" +
         model + R"(
efg: {spacing: 0.0025}
integrator: quasi_static
solver: cholmod
time_step: 0.01
gravity: [0.0, 0.0, 0.0]
fixed:
  - region: {max: [.inf, .inf, 1.0e-9]}
tools:
  - name: tool
    radius: 0.0025
    shaft_length: 0.02
    coupling_stiffness: 1.0e6
    max_force: 20.0
    contact: constraint
    grasp: {radius: 0.004}
)";
}

/// Tool pointing down (z_T = -z_S) with its tip at p.
Eigen::Isometry3d toolAt(const Eigen::Vector3d& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  X.translation() = p;
  return X;
}

constexpr double kTop = 0.03;       // block top [m]
constexpr double kRadius = 0.0025;  // tool radius [m]

/// Settled upward force on the tool with its lowest point `depth` [m] below the top.
double pressForce(TissueSimulation& sim, double depth) {
  sim.setToolPose(0, toolAt(Eigen::Vector3d(0.0, 0.0, kTop + kRadius - depth)));
  for (int k = 0; k < 12; ++k) sim.step();
  return sim.toolContact(0).f0_S.z();
}

/// Relative error of the contact model's prediction f0 + K dp of the force after one more step
/// with the tool 0.05 mm deeper; pushing deeper (-z) must raise the upward force.
double predictionError(TissueSimulation& sim) {
  const ContactLinearization c = sim.toolContact(0);
  EXPECT_TRUE(c.in_contact);
  EXPECT_LT(c.K_S(2, 2), 0.0);
  const double dz = -5e-5;
  sim.setToolPose(0, toolAt(c.p0_S + Eigen::Vector3d(0.0, 0.0, dz)));
  sim.step();
  const double change = sim.toolContact(0).f0_S.z() - c.f0_S.z();
  EXPECT_GT(change, 0.0);
  return std::abs(c.K_S(2, 2) * dz - change) / change;
}

RuntimeScene parsed(const std::string& model, const std::string& type, int resolution) {
  return parseRuntimeScene(blockScene(model, type, resolution), "block.yaml");
}

TEST(EfgContact, PressForceLiesBetweenTheTetAnswersOfTheSameBlock) {
  constexpr double kDepth = 0.001;
  TissueSimulation tet4(parsed("corotational", "tet4", 8));
  TissueSimulation tet10(parsed("corotational", "tet10", 8));
  TissueSimulation efg(parsed("efg", "tet4", 8));
  const double f4 = pressForce(tet4, kDepth);
  const double f10 = pressForce(tet10, kDepth);
  const double fe = pressForce(efg, kDepth);
  RecordProperty("force_tet4_N", std::to_string(f4));
  RecordProperty("force_tet10_N", std::to_string(f10));
  RecordProperty("force_efg_N", std::to_string(fe));
  // A 5 mm tool on 7.5 mm elements: the linear tets are much too stiff, the tet10 answer is the
  // better one; the EFG answer (particles every 5 mm) lies between them, within 15 % of tet10.
  ASSERT_GT(f10, 0.0);
  EXPECT_LT(f10, f4);
  EXPECT_GT(fe, f10) << "tet4 " << f4 << " N, tet10 " << f10 << " N";
  EXPECT_LT(fe, 1.15 * f10) << "tet4 " << f4 << " N, tet10 " << f10 << " N";
  // The haptic contact model.
  const double e4 = predictionError(tet4);
  const double e10 = predictionError(tet10);
  const double ee = predictionError(efg);
  RecordProperty("prediction_error_tet4", std::to_string(e4));
  RecordProperty("prediction_error_tet10", std::to_string(e10));
  RecordProperty("prediction_error_efg", std::to_string(ee));
  // Within 10 % of the next step, as the palpation rostest asks. At this 1 mm press the tets
  // predict within 0.2 %, EFG within 1 %; the EFG error grows with the press (11 % at 3 mm).
  EXPECT_LT(e4, 0.1);
  EXPECT_LT(e10, 0.1);
  EXPECT_LT(ee, 0.1);
  // Force on the tissue = W^T (contact forces on the vertices): it balances the tool's force.
  EXPECT_NEAR(efg.appliedContactForce().reshaped(3, efg.model().numNodes()).rowwise().sum().z(),
              -efg.toolContact(0).f0_S.z(), 1e-9);
}

TEST(EfgContact, GraspedSurfaceFollowsTheTool) {
  TissueSimulation sim(parsed("efg", "tet4", 12));
  const Eigen::Vector3d tip(0.0, 0.0, kTop + 0.001);
  sim.setToolPose(0, toolAt(tip));
  sim.setGrasp(0, true);
  sim.step();
  const Eigen::Vector3d lift(0.0, 0.0, 0.003);
  sim.setToolPose(0, toolAt(tip + lift));
  for (int k = 0; k < 5; ++k) EXPECT_EQ(sim.step().report.status, StepStatus::Ok);
  // The surface vertex under the tip rises with the jaws (its particles move rigidly with them).
  int top_centre = -1;
  double best = 1e9;
  for (const int v : sim.surface().nodes) {
    const double d = (sim.mesh().nodes.col(v) - Eigen::Vector3d(0.0, 0.0, kTop)).norm();
    if (d < best) best = d, top_centre = v;
  }
  const double rise = sim.surfacePositions()[3 * top_centre + 2] - kTop;
  EXPECT_NEAR(rise, lift.z(), 0.05 * lift.z());
  ASSERT_TRUE(sim.toolContact(0).in_contact);
  EXPECT_LT(sim.toolContact(0).f0_S.z(), 0.0);  // the tissue pulls the jaws down
}

TEST(EfgContact, TetSurfacePositionsAreTheStateBitForBit) {
  TissueSimulation sim(parsed("corotational", "tet4", 8));
  for (int k = 0; k < 5; ++k) {
    sim.setToolPose(0, toolAt(Eigen::Vector3d(0.0, 0.0, kTop + kRadius - 4e-4 * k)));
    sim.step();
  }
  ASSERT_GT(sim.contactNodes().size(), 0u);
  for (const int v : sim.surface().nodes)
    EXPECT_EQ(Eigen::Vector3d(sim.surfacePositions().segment<3>(3 * v)),
              Eigen::Vector3d(sim.state().x.segment<3>(3 * v)));
}

}  // namespace
}  // namespace surgical_sim::core
