#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "scene_blade.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace surgical_sim::core {
namespace {

RuntimeScene palpationScene() {
  return loadRuntimeScene(std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/scenes/palpation.yaml");
}

bool has(const std::vector<std::string>& list, const std::string& item) {
  for (const auto& s : list)
    if (s == item) return true;
  return false;
}

/// Tool pointing down (z_T = -z_S) with its tip at p.
Eigen::Isometry3d toolAt(const Eigen::Vector3d& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  X.translation() = p;
  return X;
}

double topOfTissue(const TissueSimulation& sim) {
  double top = -1e9;
  for (int n = 0; n < sim.mesh().numNodes(); ++n)
    if (std::abs(sim.mesh().nodes(0, n)) < 5e-3 && std::abs(sim.mesh().nodes(1, n)) < 5e-3)
      top = std::max(top, sim.state().x[3 * n + 2]);
  return top;
}

TEST(TissueSimulation, SceneWithoutToolsOrDampingBuildsNeither) {
  RuntimeScene scene = palpationScene();
  scene.tools.clear();
  scene.damping_mass = scene.damping_stiffness = 0.0;
  TissueSimulation sim(scene);
  EXPECT_FALSE(has(sim.components(), "contact"));
  EXPECT_FALSE(has(sim.components(), "damping"));
  for (int k = 0; k < 3; ++k) {
    const SimulationStepStats s = sim.step();
    EXPECT_EQ(s.collision_seconds, 0.0);
    EXPECT_EQ(s.contact_seconds, 0.0);
    EXPECT_EQ(s.contacts, 0);
    EXPECT_GT(s.integrate_seconds, 0.0);
  }
  EXPECT_EQ(sim.toolContact(0).in_contact, false);
}

TEST(TissueSimulation, PalpationForceRisesWithIndentationAndVanishesAway) {
  RuntimeScene scene = palpationScene();
  scene.gravity.setZero();
  TissueSimulation sim(scene);
  ASSERT_TRUE(has(sim.components(), "contact"));
  const double top = topOfTissue(sim);
  double previous = 0.0;
  for (int mm = 1; mm <= 8; ++mm) {
    sim.setToolPose(0, toolAt(Eigen::Vector3d(0, 0, top + 0.0025 - 1e-3 * mm)));
    for (int k = 0; k < 60; ++k) sim.step();
    const ContactLinearization c = sim.toolContact(0);
    ASSERT_TRUE(c.in_contact) << mm;
    EXPECT_GT(c.f0_S.z(), previous) << "force must grow with indentation (" << mm << " mm)";
    EXPECT_LT(std::abs(c.f0_S.x()) + std::abs(c.f0_S.y()), 0.2 * c.f0_S.z());
    EXPECT_LE(c.K_S(2, 2), 0.0);  // df/dp: pushing down (-z) raises the upward force
    previous = c.f0_S.z();
  }
  sim.setToolPose(0, toolAt(Eigen::Vector3d(0, 0, top + 0.05)));
  for (int k = 0; k < 100; ++k) sim.step();
  EXPECT_FALSE(sim.toolContact(0).in_contact);
  EXPECT_EQ(sim.toolContact(0).f0_S.norm(), 0.0);
  sim.reset();
  EXPECT_EQ(sim.state().x, sim.model().restPositions());
}

using test::bladeDown;

double totalMass(const TissueSimulation& sim) { return sim.model().lumpedMass().sum() / 3.0; }

TEST(TissueSimulation, CutThroughSplitsTheOrganKeepsItsMassAndKeepsStepping) {
  TissueSimulation sim(palpationScene());
  const double mass = totalMass(sim);
  EXPECT_FALSE(has(sim.components(), "cutting"));
  EXPECT_EQ(sim.step().cut_seconds, 0.0);
  sim.requestCut(bladeDown(0.0031, 0.05, 0.0));  // shallow: stops at mid-height
  SimulationStepStats s = sim.step();
  EXPECT_TRUE(s.topology_changed);
  EXPECT_GT(s.cut_seconds, 0.0);
  EXPECT_TRUE(has(sim.components(), "cutting"));
  EXPECT_EQ(sim.numComponents(), 1);
  sim.requestCut(bladeDown(0.0031, 0.0, -0.05));  // the rest of the way
  s = sim.step();
  // The step right after the separation may stop its energy line search early (NotConverged:
  // finite and usable); it must not fail.
  EXPECT_TRUE(s.report.status == StepStatus::Ok || s.report.status == StepStatus::NotConverged);
  EXPECT_EQ(sim.numComponents(), 2);
  EXPECT_NEAR(totalMass(sim), mass, 1e-12 * mass);
  EXPECT_EQ(sim.cutFaces().size(), static_cast<std::size_t>(sim.surface().triangles.cols()));
  int cut_faces = 0;
  for (bool c : sim.cutFaces()) cut_faces += c;
  EXPECT_GT(cut_faces, 0);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(sim.step().report.status, StepStatus::Ok);
  EXPECT_TRUE(sim.state().x.allFinite());
  EXPECT_THROW(sim.requestCut(BladeSweep{}), std::invalid_argument);
  sim.reset();
  EXPECT_EQ(sim.numComponents(), 1);
  EXPECT_FALSE(has(sim.components(), "cutting"));
}

/// Positions and velocities after each of 8 steps of the palpation scene with the tool pressing
/// in from above while the blade cuts down through the organ in 4 mm steps, and the number of
/// tool contacts over the steps.
struct PressAndCut {
  std::vector<Eigen::VectorXd> trajectory;
  int contacts = 0;
};

PressAndCut pressAndCut(TissueSimulation& sim) {
  PressAndCut run;
  for (int k = 0; k < 8; ++k) {
    sim.setToolPose(0, toolAt(Eigen::Vector3d(0.0, 0.01, 0.028 - 0.001 * k)));
    sim.requestCut(bladeDown(0.0031, 0.03 - 0.004 * k, 0.026 - 0.004 * k));
    run.contacts += sim.step().contacts;
    run.trajectory.push_back(sim.state().x);
    run.trajectory.push_back(sim.state().v);
  }
  return run;
}

TEST(TissueSimulation, ModelAfterACutIsStressFreeAtRestWithTheBlocksOfTheCutMesh) {
  TissueSimulation sim(palpationScene());
  const double mass = totalMass(sim);
  int changes = 0;
  for (int k = 0; k < 8; ++k) {
    sim.requestCut(bladeDown(0.0031, 0.03 - 0.004 * k, 0.026 - 0.004 * k));
    if (!sim.step().topology_changed) continue;
    ++changes;
    const TissueModel& model = sim.model();
    const TetMesh& mesh = sim.mesh();
    ASSERT_EQ(model.restPositions(),
              Eigen::Map<const Eigen::VectorXd>(mesh.nodes.data(), 3 * mesh.numNodes()));
    EXPECT_NEAR(totalMass(sim), mass, 1e-12 * mass);
    // Rest gradients of every copy reproduce its rest shape: F = I, no energy, no force.
    const Eigen::VectorXd& X = model.restPositions();
    EXPECT_LT(std::abs(model.energy(X)), 1e-18);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(X.size());
    model.addInternalForce(X, f);
    EXPECT_LT(f.lpNorm<Eigen::Infinity>(), 1e-12);  // [N]
    // The stiffness couples exactly the nodes that share an element, in full 3 x 3 blocks.
    std::vector<Eigen::Triplet<double>> blocks;
    for (int e = 0; e < mesh.numElements(); ++e)
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
          for (int i = 0; i < 9; ++i)
            blocks.emplace_back(3 * mesh.elements(a, e) + i % 3, 3 * mesh.elements(b, e) + i / 3,
                                1.0);
    Eigen::SparseMatrix<double> expected(X.size(), X.size());
    expected.setFromTriplets(blocks.begin(), blocks.end());
    const Eigen::SparseMatrix<double>& pattern = model.stiffnessPattern();
    ASSERT_EQ(pattern.nonZeros(), expected.nonZeros());
    EXPECT_TRUE(std::equal(pattern.outerIndexPtr(), pattern.outerIndexPtr() + X.size() + 1,
                           expected.outerIndexPtr()));
    EXPECT_TRUE(std::equal(pattern.innerIndexPtr(), pattern.innerIndexPtr() + pattern.nonZeros(),
                           expected.innerIndexPtr()));
  }
  EXPECT_GE(changes, 3);
}

TEST(TissueSimulation, ReplayThroughCutsAfterResetIsBitIdentical) {
  TissueSimulation sim(palpationScene());
  const int uncut_nodes = sim.mesh().numNodes();
  const PressAndCut first = pressAndCut(sim);
  EXPECT_GT(sim.mesh().numNodes(), uncut_nodes);
  EXPECT_GT(first.contacts, 0);
  sim.reset();
  const PressAndCut replay = pressAndCut(sim);
  EXPECT_EQ(replay.contacts, first.contacts);
  ASSERT_EQ(replay.trajectory.size(), first.trajectory.size());
  for (std::size_t i = 0; i < first.trajectory.size(); ++i) {
    EXPECT_EQ(replay.trajectory[i], first.trajectory[i]) << i;
  }
}

TEST(TissueSimulation, BackgroundCholeskySolverFollowsTheDirectSolverThroughACut) {
  // Each cut appends nodes: pcg_cholesky_background goes on with its old factor (plus
  // block-Jacobi on the new nodes) or falls back to a synchronous factorization, and must give
  // the direct solver's steps to the PCG tolerance (amplified by the dynamics of the cut organ).
  RuntimeScene scene = palpationScene();
  scene.pcg_tolerance = 1e-10;
  TissueSimulation direct(scene);
  scene.solver = SolverKind::PcgCholeskyBackground;
  TissueSimulation background(scene);
  EXPECT_TRUE(has(background.components(), "integrator:implicit_euler_linearized"));
  for (int k = 0; k < 6; ++k) {
    if (k == 1 || k == 2) {
      const BladeSweep sweep =
          k == 1 ? bladeDown(0.0031, 0.05, 0.0) : bladeDown(0.0031, 0.0, -0.05);
      direct.requestCut(sweep);
      background.requestCut(sweep);
    }
    const StepStatus expected = direct.step().report.status;
    ASSERT_EQ(background.step().report.status, expected) << "step " << k;
    ASSERT_EQ(background.state().x.size(), direct.state().x.size());
    EXPECT_LT((background.state().x - direct.state().x).lpNorm<Eigen::Infinity>(), 1e-9)
        << "step " << k;  // [m]
  }
  EXPECT_EQ(background.numComponents(), 2);
}

TEST(TissueSimulation, CuttingSceneCutThroughByAMovingVerticalBladeGivesTwoPieces) {
  // The motion of test/data/cutting.bag: a vertical 70 mm blade (tip 11 mm below the organ)
  // crossing the organ along y at x = 3.1 mm in 100 steps, with the tool tip moving with it.
  TissueSimulation sim(
      loadRuntimeScene(std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/scenes/cutting.yaml"));
  const double mass = totalMass(sim);
  const double tip_z = -0.036, x = 0.0031;
  auto blade = [&](double y) {
    Eigen::Matrix3Xd b(3, 2);
    b << x, x, y, y, tip_z, tip_z + 0.07;
    return b;
  };
  for (int k = 0; k < 100; ++k) {
    const double y0 = -0.07 + 0.0014 * k, y1 = y0 + 0.0014;
    sim.setToolPose(0, toolAt(Eigen::Vector3d(x, y1, tip_z)));
    sim.requestCut(BladeSweep{blade(y0), blade(y1)});
    const StepStatus status = sim.step().report.status;
    ASSERT_TRUE(status == StepStatus::Ok || status == StepStatus::NotConverged) << "step " << k;
    if (k == 50) {
      EXPECT_EQ(sim.numComponents(), 1);  // half-way across: still one piece
    }
  }
  for (int k = 0; k < 20; ++k) sim.step();
  EXPECT_EQ(sim.numComponents(), 2);
  EXPECT_NEAR(totalMass(sim), mass, 1e-12 * mass);
  EXPECT_TRUE(sim.state().x.allFinite());
}

}  // namespace
}  // namespace surgical_sim::core
