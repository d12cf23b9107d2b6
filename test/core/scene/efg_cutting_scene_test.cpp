// Cutting a meshless EFG body in the running simulation: a blade through a cantilevered box
// splits it in two without adding DOFs or losing mass, the surface stays closed and manifold
// with every vertex following the material on its own side, the free piece falls away, and a
// blade that misses changes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "scene_blade.h"
#include "surgical_sim/core/mesh/surface_closure.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace surgical_sim::core {
namespace {

constexpr double kLength = 0.04;  // box along x [m], fixed at x = 0
constexpr double kHeight = 0.02;  // box along y and z [m]
constexpr double kCutX = 0.0301;  // blade plane [m], off the particle and IP grid planes

/// A 40 x 20 x 20 mm efg box (2.5 mm IP cells) fixed at x = 0, under gravity, no tools; `extra`
/// (YAML) is appended.
RuntimeScene boxScene(const std::string& extra = "") {
  return parseRuntimeScene(R"(
name: efg_cut_box
mesh: {generator: box, size: [0.04, 0.02, 0.02], resolution: [8, 4, 4]}
material: {young_modulus: 2.0e4, poisson_ratio: 0.4, density: 1000.0}
model: efg
efg: {spacing: 0.0025}
integrator: implicit_euler_linearized
solver: cholmod
time_step: 0.01
gravity: [0.0, 0.0, -9.81]
damping: {mass: 1.0, stiffness: 0.0}
fixed:
  - region: {max: [1.0e-9, .inf, .inf]}
)" + extra,
                           "efg_cut_box.yaml");
}

/// The blade across the box at x = kCutX moving down from z_from to z_to [m].
BladeSweep bladeDown(double z_from, double z_to) { return test::bladeDown(kCutX, z_from, z_to); }

/// +1 beyond the cut plane, -1 before it.
int side(double x) { return x > kCutX ? 1 : -1; }

TEST(EfgCuttingScene, CutThroughSplitsTheBoxKeepsMassAndDofsAndTheFreePieceFalls) {
  TissueSimulation sim(boxScene());
  const double mass = sim.model().lumpedMass().sum();
  const Eigen::Index dofs = sim.state().x.size();
  const Eigen::Index triangles = sim.surface().triangles.cols();
  EXPECT_EQ(sim.numComponents(), 1);
  // Down through the whole height in 4 steps.
  for (int k = 0; k < 4; ++k) {
    sim.requestCut(bladeDown(0.025 - 0.008 * k, 0.017 - 0.008 * k));
    const SimulationStepStats s = sim.step();
    EXPECT_NE(s.report.status, StepStatus::SolverFailed) << sim.cutError();
    EXPECT_TRUE(sim.cutError().empty()) << sim.cutError();
  }
  EXPECT_EQ(sim.numComponents(), 2);
  EXPECT_EQ(sim.state().x.size(), dofs);
  EXPECT_NEAR(sim.model().lumpedMass().sum(), mass, 1e-12 * mass);
  EXPECT_GT(sim.surface().triangles.cols(), triangles);
  const SurfaceClosure closure = checkSurfaceClosure(sim.surface().triangles);
  EXPECT_EQ(closure.open_edges, 0);
  EXPECT_EQ(closure.pinched_edges, 0);
  ASSERT_EQ(sim.cutFaces().size(), static_cast<std::size_t>(sim.surface().triangles.cols()));
  int cut_faces = 0;
  for (bool c : sim.cutFaces()) cut_faces += c;
  EXPECT_GT(cut_faces, 0);

  // Every vertex follows particles of one side only: a vertex of the outer surface its own side,
  // the vertices of the cut sheets (placed where the blade met the sagging box) both sides.
  std::vector<bool> on_sheet(static_cast<std::size_t>(sim.mesh().numNodes()), false);
  for (Eigen::Index t = 0; t < sim.surface().triangles.cols(); ++t)
    if (sim.cutFaces()[static_cast<std::size_t>(t)])
      for (int c = 0; c < 3; ++c)
        on_sheet[static_cast<std::size_t>(sim.surface().triangles(c, t))] = true;
  const Eigen::VectorXd& rest = sim.model().restPositions();
  int sheet_sides[2] = {0, 0};
  for (int v : sim.surface().nodes) {
    const SurfaceMapping::Row row = sim.surfaceMapping().row(v);
    ASSERT_GT(row.size, 0) << "vertex " << v;
    const int first = side(rest[3 * row.nodes[0]]);
    for (int k = 1; k < row.size; ++k)
      EXPECT_EQ(side(rest[3 * row.nodes[k]]), first) << "vertex " << v;
    const double x = sim.mesh().nodes(0, v);
    if (on_sheet[static_cast<std::size_t>(v)]) {
      ++sheet_sides[first > 0];
    } else {
      EXPECT_EQ(first, side(x)) << "vertex " << v << " at x = " << x;
    }
  }
  EXPECT_GT(sheet_sides[0], 0);
  EXPECT_GT(sheet_sides[1], 0);

  // The piece beyond the cut falls free; the cantilever stays; the lips separate.
  for (int k = 0; k < 20; ++k) {
    const StepStatus status = sim.step().report.status;
    EXPECT_TRUE(status == StepStatus::Ok || status == StepStatus::NotConverged) << toString(status);
  }
  ASSERT_TRUE(sim.state().x.allFinite());
  ASSERT_TRUE(sim.surfacePositions().allFinite());
  double fallen = 0.0, kept = 0.0;
  int beyond = 0, before = 0;
  for (int v : sim.surface().nodes) {
    const double dz = sim.surfacePositions()[3 * v + 2] - sim.mesh().nodes(2, v);
    const double x = sim.mesh().nodes(0, v);
    if (x > kCutX + 1e-6) {
      fallen += dz;
      ++beyond;
    } else if (x < kCutX - 1e-6) {
      kept += dz;
      ++before;
    }
  }
  fallen /= beyond;
  kept /= before;
  // 0.2 s of free fall with mass damping 1/s: about 0.17 m; the 2 cm stub sags by millimetres.
  EXPECT_LT(fallen, -0.1);
  EXPECT_GT(kept, -0.01);
}

TEST(EfgCuttingScene, HostileSweepsNeverReportOkWithAbsurdNumbers) {
  // 60 steps of random fast, deep sweeps (2- and 3-point blades anywhere within 10 cm, moving up
  // to 10 cm a step, i.e. 10 m/s, many spanning and cutting the box through) while it sags and
  // falls apart. A step that reports ok has finite particle and surface positions within a metre
  // of rest, the mass is kept and every cut is applied or rejected by name.
  TissueSimulation sim(boxScene());
  const double mass = sim.model().lumpedMass().sum();
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto point = [&] {
    return Eigen::Vector3d(0.02 + 0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng));
  };
  int ok = 0;
  for (int k = 0; k < 60; ++k) {
    BladeSweep sweep;
    const int points = 2 + static_cast<int>(rng() % 2);
    sweep.start.resize(3, points);
    for (int i = 0; i < points; ++i) sweep.start.col(i) = point();
    sweep.end = sweep.start.colwise() + 0.1 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    sim.requestCut(sweep);
    const SimulationStepStats s = sim.step();
    if (s.report.status != StepStatus::Ok) continue;
    ++ok;
    const Eigen::VectorXd& x = sim.state().x;
    ASSERT_TRUE(x.allFinite()) << "step " << k;
    ASSERT_TRUE(sim.surfacePositions().allFinite()) << "step " << k;
    EXPECT_LT((x - sim.model().restPositions()).cwiseAbs().maxCoeff(), 1.0) << "step " << k;
    EXPECT_NEAR(sim.model().lumpedMass().sum(), mass, 1e-12 * mass) << "step " << k;
  }
  EXPECT_GT(ok, 50);
  EXPECT_GT(sim.numComponents(), 1);
  const SurfaceClosure closure = checkSurfaceClosure(sim.surface().triangles);
  EXPECT_EQ(closure.open_edges, 0);
  EXPECT_EQ(closure.pinched_edges, 0);
}

TEST(EfgCuttingScene, ToolPressingGraspingAndCuttingAtRandomNeverReportsOkWithAbsurdNumbers) {
  // 200 steps of a user at their worst on a box with a grasping tool: the tool jumps around and
  // into the box (sometimes 1 m away, sometimes a NaN pose), its jaws open and close at random,
  // and a third of the steps also sweep a random blade, often through where the tool presses.
  // A step that is not a failure has finite positions within a metre of rest, the tool force
  // within its cap, the mass kept; the surface stays closed.
  constexpr double kMaxForce = 5.0;
  TissueSimulation sim(boxScene(R"(
tools:
  - name: tool
    radius: 0.002
    shaft_length: 0.02
    coupling_stiffness: 1.0e4
    max_force: 5.0
    contact: constraint
    grasp: {radius: 0.004}
)"));
  const double mass = sim.model().lumpedMass().sum();
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int ok = 0, cuts = 0, contacts = 0;
  for (int k = 0; k < 200; ++k) {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() =
        Eigen::AngleAxisd(M_PI + 0.5 * u(rng), Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Vector3d tip(0.02 + 0.025 * u(rng), 0.01 + 0.015 * u(rng), 0.018 + 0.006 * u(rng));
    X.translation() = tip;
    if (rng() % 20 == 0) X.translation().x() += 1.0;
    if (rng() % 25 == 0) X.translation().y() = std::nan("");
    sim.setToolPose(0, X);
    if (rng() % 4 == 0) sim.setGrasp(0, rng() % 2 == 0);
    if (rng() % 3 == 0) {
      BladeSweep sweep;
      sweep.start.resize(3, 2);
      const Eigen::Vector3d half = 0.02 * Eigen::Vector3d(u(rng), u(rng), 0.2 * u(rng));
      sweep.start << tip - half, tip + half;
      sweep.start.row(2).array() += 0.01;
      const double depth = 0.0275 + 0.0125 * u(rng);  // half of them through the whole height
      sweep.end = sweep.start.colwise() + Eigen::Vector3d(0.005 * u(rng), 0.005 * u(rng), -depth);
      sim.requestCut(sweep);
      ++cuts;
    }
    const SimulationStepStats s = sim.step();
    const StepStatus status = s.report.status;
    if (status == StepStatus::SolverFailed || status == StepStatus::NonFinite ||
        status == StepStatus::BlowUp)
      continue;
    ++ok;
    const Eigen::VectorXd& x = sim.state().x;
    ASSERT_TRUE(x.allFinite()) << "step " << k;
    ASSERT_TRUE(sim.surfacePositions().allFinite()) << "step " << k;
    EXPECT_LT((x - sim.model().restPositions()).cwiseAbs().maxCoeff(), 1.0) << "step " << k;
    const ContactLinearization c = sim.toolContact(0);
    contacts += c.in_contact;
    EXPECT_LE(c.f0_S.norm(), kMaxForce * (1.0 + 1e-6)) << "step " << k << " " << toString(status);
    EXPECT_NEAR(sim.model().lumpedMass().sum(), mass, 1e-12 * mass) << "step " << k;
  }
  EXPECT_GT(ok, 150);
  EXPECT_GT(cuts, 50);
  EXPECT_GT(contacts, 20);
  EXPECT_GT(sim.numComponents(), 1);
  const SurfaceClosure closure = checkSurfaceClosure(sim.surface().triangles);
  EXPECT_EQ(closure.open_edges, 0);
  EXPECT_EQ(closure.pinched_edges, 0);
}

TEST(EfgCuttingScene, BladeThatMissesChangesNothing) {
  TissueSimulation cut(boxScene());
  TissueSimulation uncut(boxScene());
  const Eigen::Index triangles = cut.surface().triangles.cols();
  const double mass = cut.model().lumpedMass().sum();
  for (int k = 0; k < 3; ++k) {
    cut.requestCut(bladeDown(0.05, 0.03));  // above the box, which sags away from it
    const SimulationStepStats s = cut.step();
    uncut.step();
    EXPECT_FALSE(s.topology_changed);
    EXPECT_EQ(s.report.status, StepStatus::Ok);
  }
  EXPECT_EQ(cut.numComponents(), 1);
  EXPECT_EQ(cut.surface().triangles.cols(), triangles);
  EXPECT_EQ(cut.model().lumpedMass().sum(), mass);
  EXPECT_EQ(cut.state().x, uncut.state().x);
  for (bool c : cut.cutFaces()) EXPECT_FALSE(c);
}

TEST(EfgCuttingScene, NoNewCutStartsOnceTheSurfaceIsAtItsBudget) {
  // A budget just above the uncut surface: the first cut runs to its end (it started below the
  // budget), then a second blade through the box is refused step by step, by name, changing
  // nothing, while a blade away from the body still steps ok.
  RuntimeScene scene = boxScene();
  const int uncut = static_cast<int>(TissueSimulation(scene).surface().triangles.cols());
  scene.efg_max_cut_triangles = uncut + 1;
  TissueSimulation sim(scene);
  for (int k = 0; k < 4; ++k) {
    sim.requestCut(bladeDown(0.025 - 0.008 * k, 0.017 - 0.008 * k));
    EXPECT_NE(sim.step().report.status, StepStatus::CutRefused) << sim.cutError();
  }
  ASSERT_EQ(sim.numComponents(), 2);
  const Eigen::Index triangles = sim.surface().triangles.cols();
  ASSERT_GT(triangles, uncut);
  const double mass = sim.model().lumpedMass().sum();
  for (int k = 0; k < 4; ++k) {
    sim.requestCut(test::bladeDown(0.0151, 0.025 - 0.008 * k, 0.017 - 0.008 * k));
    const SimulationStepStats s = sim.step();
    EXPECT_EQ(s.report.status, StepStatus::CutRefused) << "step " << k;
    EXPECT_FALSE(s.topology_changed);
    EXPECT_NE(sim.cutError().find("efg.max_cut_triangles = " + std::to_string(uncut + 1)),
              std::string::npos)
        << sim.cutError();
    EXPECT_NE(sim.cutError().find(std::to_string(triangles) + " triangles"), std::string::npos)
        << sim.cutError();
  }
  EXPECT_EQ(sim.numComponents(), 2);
  EXPECT_EQ(sim.surface().triangles.cols(), triangles);
  EXPECT_EQ(sim.model().lumpedMass().sum(), mass);
  ASSERT_TRUE(sim.state().x.allFinite());
  sim.requestCut(bladeDown(0.5, 0.4));  // far above the box
  const SimulationStepStats away = sim.step();
  EXPECT_NE(away.report.status, StepStatus::CutRefused);
  EXPECT_TRUE(sim.cutError().empty()) << sim.cutError();
  EXPECT_STREQ(toString(StepStatus::CutRefused), "cut_refused");
}

TEST(EfgCuttingScene, AStarOfCracksThroughOnePointStaysWithinTheBudget) {
  // Cracks through one point of the top face at golden angles, each entering the top and ending
  // under it within one step, refine the surface around that point more with every cut. With a
  // budget, the cuts stop starting once it is reached: the surface stays closed and bounded, and
  // every step is ok or says why it did not cut.
  RuntimeScene scene = boxScene();
  scene.efg_max_cut_triangles = 2000;  // reached after about 40 cuts
  scene.gravity.setZero();
  TissueSimulation sim(scene);
  const Eigen::Vector3d centre(0.021, 0.0101, kHeight);
  int refused = 0, largest = 0;
  for (int k = 0; k < 60; ++k) {
    const double angle = 2.399963 * k;
    const Eigen::Vector3d half = 0.015 * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0);
    BladeSweep sweep;
    sweep.start.resize(3, 2);
    sweep.start << centre - half, centre + half;
    sweep.start.row(2).array() += 0.001;
    sweep.end = sweep.start;
    sweep.end.row(2).array() -= 0.002;
    sim.requestCut(sweep);
    const StepStatus status = sim.step().report.status;
    refused += status == StepStatus::CutRefused;
    EXPECT_TRUE(status == StepStatus::Ok || status == StepStatus::CutRefused) << toString(status);
    largest = std::max(largest, static_cast<int>(sim.surface().triangles.cols()));
  }
  EXPECT_GT(refused, 10);
  EXPECT_LT(largest, 2 * scene.efg_max_cut_triangles);
  const SurfaceClosure closure = checkSurfaceClosure(sim.surface().triangles);
  EXPECT_EQ(closure.open_edges, 0);
  EXPECT_EQ(closure.pinched_edges, 0);
}

TEST(EfgCuttingScene, ResetRestoresTheUncutBody) {
  TissueSimulation sim(boxScene());
  const Eigen::Index triangles = sim.surface().triangles.cols();
  for (int k = 0; k < 4; ++k) {
    sim.requestCut(bladeDown(0.025 - 0.008 * k, 0.017 - 0.008 * k));
    sim.step();
  }
  ASSERT_EQ(sim.numComponents(), 2);
  sim.reset();
  EXPECT_EQ(sim.numComponents(), 1);
  EXPECT_EQ(sim.surface().triangles.cols(), triangles);
  EXPECT_TRUE(sim.cutFaces().empty());
  EXPECT_EQ(sim.state().x, sim.model().restPositions());
}

}  // namespace
}  // namespace surgical_sim::core
