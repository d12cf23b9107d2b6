#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "rigid_node_test_util.h"
#include "surgical_sim/core/connective/rigid_node_implicit_euler.h"
#include "surgical_sim/core/connective/rigid_node_quasi_static.h"
#include "surgical_sim/core/connective/rigid_node_sampling.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/surface.h"

namespace surgical_sim::core {
namespace {

/// All six DOFs of the rigid nodes with rest x <= x_max.
std::vector<int> clampedDofs(const RigidNodeConfiguration& rest, double x_max) {
  std::vector<int> dofs;
  for (int i = 0; i < rest.numNodes(); ++i)
    if (rest.p_TN[i].x() <= x_max)
      for (int c = 0; c < kRigidNodeDofs; ++c) dofs.push_back(kRigidNodeDofs * i + c);
  return dofs;
}

/// Mean displacement along axis `component` (y by default) of the rigid nodes with rest
/// x >= x_min [m].
double meanDeflection(const RigidNodeConfiguration& rest, const RigidNodeConfiguration& q,
                      double x_min, int component = 1) {
  double sum = 0.0;
  int count = 0;
  for (int i = 0; i < rest.numNodes(); ++i) {
    if (rest.p_TN[i].x() < x_min) continue;
    sum += q.p_TN[i][component] - rest.p_TN[i][component];
    ++count;
  }
  return sum / count;
}

/// Quasi-static equilibrium of model under gravity with the rigid nodes at rest x <= 0 clamped,
/// from q (solved in place).
StepReport solveClampedUnderGravity(const RigidNodeModel& model, RigidNodeConfiguration& q) {
  RigidNodeProblem problem;
  problem.model = &model;
  problem.body_acceleration = Eigen::Vector3d(0, -9.81, 0);
  problem.fixed_dofs = clampedDofs(model.restConfiguration(), 0.0);
  RigidNodeQuasiStatic solver;
  return solver.solve(problem, q);
}

void expectUnitQuaternions(const RigidNodeConfiguration& q) {
  for (int i = 0; i < q.numNodes(); ++i) EXPECT_NEAR(q.q_TN[i].norm(), 1.0, 1e-14);
}

TEST(RigidNodeIncrement, QuaternionUpdateKeepsUnitNormAndMovesAttachedPointsToFirstOrder) {
  std::mt19937 rng(2);
  RigidNodeConfiguration q = test::randomLayout(1, 3, 3, 2).rest;
  Eigen::VectorXd dq(18);
  for (int step = 0; step < 2000; ++step) {
    for (int k = 0; k < 18; ++k) dq[k] = std::uniform_real_distribution<double>(-3.0, 3.0)(rng);
    applyRigidNodeIncrement(dq, 1.0, q);
  }
  expectUnitQuaternions(q);
  // A point attached to node 1 moves by dx + dtheta x (p - x) to first order.
  const Eigen::Vector3d local(0.3, -0.2, 0.5);
  const Eigen::Vector3d before = q.p_TN[1] + q.q_TN[1] * local;
  dq.setZero();
  dq.segment<3>(6) = Eigen::Vector3d(1.0, 2.0, -1.0);
  dq.segment<3>(9) = Eigen::Vector3d(-0.5, 0.7, 0.2);
  const double h = 1e-7;
  RigidNodeConfiguration moved = q;
  applyRigidNodeIncrement(dq, h, moved);
  const Eigen::Vector3d velocity = (moved.p_TN[1] + moved.q_TN[1] * local - before) / h;
  const Eigen::Vector3d expected =
      dq.segment<3>(6) + Eigen::Vector3d(dq.segment<3>(9)).cross(before - q.p_TN[1]);
  EXPECT_LE((velocity - expected).norm(), 1e-6);
  test::expectInvalidArgument([&] { applyRigidNodeIncrement(Eigen::VectorXd(5), 1.0, q); },
                              "increment size 5");
}

/// A block 2 x 0.4 x 0.4 m (E = 20 MPa) clamped at x = 0, under gravity.
struct Block {
  RigidNodeLayout layout =
      trilinearGridLayout(Eigen::Vector3d(0, -0.2, -0.2), Eigen::Vector3d(2.0, 0.4, 0.4),
                          Eigen::Vector3i(5, 2, 2), Material::create(2e7, 0.3, 1000.0));
  RigidNodeModel model{layout.rest, layout.samples};
  RigidNodeProblem problem;
  Block() {
    problem.model = &model;
    problem.body_acceleration = Eigen::Vector3d(0, -9.81, 0);
    problem.fixed_dofs = clampedDofs(layout.rest, 0.0);
  }
};

TEST(RigidNodeQuasiStatic, NewtonConvergesQuadraticallyToEquilibrium) {
  Block block;
  RigidNodeConfiguration q = block.layout.rest;
  RigidNodeQuasiStatic solver;
  const StepReport report = solver.solve(block.problem, q);
  ASSERT_EQ(report.status, StepStatus::Ok);
  EXPECT_LE(report.newton_iterations, 6);
  EXPECT_LE(report.residual, 1e-9);
  expectUnitQuaternions(q);
  // The total force on the free DOFs vanishes; the clamped nodes carry the weight.
  Eigen::VectorXd f = Eigen::VectorXd::Zero(block.model.numDofs());
  block.model.addInternalForce(q, f);
  block.model.addBodyForce(q, block.problem.body_acceleration, f);
  Eigen::Vector3d reaction = Eigen::Vector3d::Zero();
  for (int i = 0; i < block.model.numNodes(); ++i) {
    if (block.layout.rest.p_TN[i].x() > 0.0) {
      EXPECT_LE(f.segment<6>(6 * i).norm(), 1e-6 * block.model.totalMass() * 9.81);
    } else {
      reaction -= f.segment<3>(6 * i);
    }
  }
  EXPECT_NEAR(reaction.y(), block.model.totalMass() * 9.81, 1e-6 * block.model.totalMass() * 9.81);
  EXPECT_LT(meanDeflection(block.layout.rest, q, 2.0), -0.01);
}

/// The T5(b) beam at 8 x 1 x 1 cells (16 x 1 x 1 m, E = 40 kPa, nu = 0.3, 5 kg, trilinear
/// weights), clamped at x = 0, loaded by gravity along -z in `increments` equal steps: every
/// increment must converge with a superlinear tail; returns the mean tip deflection [m].
double solveSaggingBeam(int increments) {
  const RigidNodeLayout layout =
      trilinearGridLayout(Eigen::Vector3d(0, -0.5, -0.5), Eigen::Vector3d(16, 1, 1),
                          Eigen::Vector3i(9, 2, 2), Material::create(4e4, 0.3, 0.3125));
  const RigidNodeModel model(layout.rest, layout.samples);
  RigidNodeProblem problem;
  problem.model = &model;
  problem.fixed_dofs = clampedDofs(layout.rest, 0.0);
  RigidNodeQuasiStatic solver;
  RigidNodeConfiguration q = layout.rest;
  for (int k = 1; k <= increments; ++k) {
    problem.body_acceleration = Eigen::Vector3d(0, 0, -9.81 * k / increments);
    const StepReport report = solver.solve(problem, q);
    EXPECT_EQ(report.status, StepStatus::Ok) << "increment " << k;
    EXPECT_LE(report.newton_iterations, 10) << "increment " << k;
    // Quadratic near the solution: the last iteration gains at least three orders of magnitude
    // (a linear rate leaves ratios near 1 and ends at the iteration cap).
    const std::vector<double>& history = solver.residualHistory();
    if (history.size() < 2) {
      ADD_FAILURE() << "increment " << k << ": no Newton iteration";
      continue;
    }
    EXPECT_LE(history.back(), 1e-9);
    EXPECT_LE(history.back(), 1e-3 * history[history.size() - 2]) << "increment " << k;
  }
  expectUnitQuaternions(q);
  return meanDeflection(layout.rest, q, 16.0, 2);
}

TEST(RigidNodeQuasiStatic, NewtonConvergesQuadraticallyAtLargeRotations) {
  // The tip sags by about a third of the length: large rotations, under which drilling modes
  // of the trilinear layout have slightly negative stiffness at equilibrium.
  const double tip4 = solveSaggingBeam(4);
  EXPECT_LT(tip4, -4.0);
  EXPECT_GT(tip4, -7.0);
  // The converged equilibrium does not depend on the load path.
  EXPECT_NEAR(solveSaggingBeam(8), tip4, 1e-6 * std::abs(tip4));
}

TEST(RigidNodeImplicitEuler, SettlesToTheQuasiStaticEquilibriumWithUnitQuaternions) {
  Block block;
  RigidNodeConfiguration equilibrium = block.layout.rest;
  RigidNodeQuasiStatic quasi_static;
  ASSERT_EQ(quasi_static.solve(block.problem, equilibrium).status, StepStatus::Ok);
  const double static_deflection = meanDeflection(block.layout.rest, equilibrium, 2.0);

  block.problem.mass_damping = 2.0;
  RigidNodeState state;
  state.configuration = block.layout.rest;
  state.velocity = Eigen::VectorXd::Zero(block.model.numDofs());
  RigidNodeImplicitEuler integrator;
  double lowest = 0.0;
  for (int step = 0; step < 400; ++step) {
    const StepReport report = integrator.step(block.problem, 0.02, state);
    ASSERT_EQ(report.status, StepStatus::Ok) << "step " << step;
    lowest = std::min(lowest, meanDeflection(block.layout.rest, state.configuration, 2.0));
  }
  expectUnitQuaternions(state.configuration);
  EXPECT_NEAR(state.time, 8.0, 1e-12);
  // It swung past the static deflection (dynamics, not a static solve) and came to rest there.
  EXPECT_LT(lowest, static_deflection);
  EXPECT_NEAR(meanDeflection(block.layout.rest, state.configuration, 2.0), static_deflection,
              1e-3 * std::abs(static_deflection));
  for (int d : block.problem.fixed_dofs) EXPECT_EQ(state.velocity[d], 0.0);
}

/// Steps the Block beam, released from rest under gravity (bending), with settings and returns
/// the rigid-node positions after each step; every step must be Ok.
std::vector<std::vector<Eigen::Vector3d>> bendBlock(const RigidNodeImplicitEulerSettings& settings,
                                                    int steps, int* factorizations = nullptr) {
  Block block;
  block.problem.mass_damping = 1.0;
  RigidNodeState state;
  state.configuration = block.layout.rest;
  state.velocity = Eigen::VectorXd::Zero(block.model.numDofs());
  RigidNodeImplicitEuler integrator(settings);
  std::vector<std::vector<Eigen::Vector3d>> positions;
  for (int step = 0; step < steps; ++step) {
    const StepReport report = integrator.step(block.problem, 0.02, state);
    EXPECT_EQ(report.status, StepStatus::Ok) << "step " << step;
    if (report.linear_iterations > 1) EXPECT_LE(report.residual, settings.relative_tolerance);
    positions.push_back(state.configuration.p_TN);
  }
  if (factorizations != nullptr) *factorizations = integrator.factorizations();
  return positions;
}

TEST(RigidNodeImplicitEuler, ReusedFactorFollowsTheDirectTrajectory) {
  RigidNodeImplicitEulerSettings direct;
  direct.refresh_interval = 1;
  RigidNodeImplicitEulerSettings reuse;
  reuse.refresh_interval = 8;
  const int steps = 24;
  int direct_factorizations = 0, reuse_factorizations = 0;
  const auto expected = bendBlock(direct, steps, &direct_factorizations);
  const auto actual = bendBlock(reuse, steps, &reuse_factorizations);
  EXPECT_EQ(direct_factorizations, steps);
  EXPECT_EQ(reuse_factorizations, 3);  // steps 0, 8, 16: the others reused a factor
  const Block block;
  double largest_motion = 0.0, largest_difference = 0.0;
  for (int step = 0; step < steps; ++step) {
    for (int i = 0; i < block.model.numNodes(); ++i) {
      largest_motion =
          std::max(largest_motion, (expected[step][i] - block.layout.rest.p_TN[i]).norm());
      largest_difference =
          std::max(largest_difference, (actual[step][i] - expected[step][i]).norm());
    }
  }
  EXPECT_GT(largest_motion, 1e-3);  // the beam bends [m]
  EXPECT_LE(largest_difference, 1e-8 * largest_motion);
}

TEST(RigidNodeImplicitEuler, RefactorizesEveryRefreshInterval) {
  for (const int interval : {1, 3, 5, 20}) {
    RigidNodeImplicitEulerSettings settings;
    settings.refresh_interval = interval;
    int factorizations = 0;
    bendBlock(settings, 20, &factorizations);
    EXPECT_EQ(factorizations, (20 + interval - 1) / interval) << "refresh_interval " << interval;
  }
}

TEST(RigidNodeImplicitEuler, RefactorizesWhenTheIterationCapIsTooSmall) {
  // One iteration cannot reach 1e-10 with a stale factor: every step falls back to a direct
  // solve, and the trajectory stays the direct one.
  RigidNodeImplicitEulerSettings direct;
  direct.refresh_interval = 1;
  RigidNodeImplicitEulerSettings capped;
  capped.max_pcg_iterations = 1;
  int factorizations = 0;
  const auto expected = bendBlock(direct, 6);
  const auto actual = bendBlock(capped, 6, &factorizations);
  EXPECT_EQ(factorizations, 6);
  for (int i = 0; i < static_cast<int>(expected.back().size()); ++i)
    EXPECT_LE((actual.back()[i] - expected.back()[i]).norm(), 1e-12);
}

TEST(RigidNodeImplicitEuler, RejectsBadSettingsNamingThem) {
  auto expectThrowNaming = [](const RigidNodeImplicitEulerSettings& settings,
                              const std::string& name) {
    try {
      RigidNodeImplicitEuler integrator(settings);
      ADD_FAILURE() << name << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  RigidNodeImplicitEulerSettings settings;
  settings.refresh_interval = 0;
  expectThrowNaming(settings, "refresh_interval");
  settings = {};
  settings.relative_tolerance = 0.0;
  expectThrowNaming(settings, "relative_tolerance");
  settings = {};
  settings.relative_tolerance = 1.0;
  expectThrowNaming(settings, "relative_tolerance");
  settings = {};
  settings.max_pcg_iterations = 0;
  expectThrowNaming(settings, "max_pcg_iterations");
}

TEST(RigidNodeImplicitEuler, FreeRigidSpinStaysRigid) {
  RigidNodeLayout layout = test::randomLayout(31, 6, 20, 4);
  for (RigidNodeSample& s : layout.samples) {  // stiff enough to make centrifugal strain small
    s.lambda *= 1e4;
    s.mu *= 1e4;
  }
  const RigidNodeModel model(layout.rest, layout.samples);
  RigidNodeProblem problem;
  problem.model = &model;
  RigidNodeState state;
  state.configuration = layout.rest;
  state.velocity = Eigen::VectorXd::Zero(model.numDofs());
  const Eigen::Vector3d omega(0.0, 0.0, 0.5), centre(0.5, 0.5, 0.5);
  for (int i = 0; i < model.numNodes(); ++i) {
    state.velocity.segment<3>(6 * i) = omega.cross(layout.rest.p_TN[i] - centre);
    state.velocity.segment<3>(6 * i + 3) = omega;
  }
  Eigen::SparseMatrix<double> M = model.stiffnessPattern();
  model.assembleNodeMass(state.configuration, M);
  const double kinetic = 0.5 * state.velocity.dot(M * state.velocity);
  RigidNodeImplicitEuler integrator;
  for (int step = 0; step < 50; ++step)
    ASSERT_EQ(integrator.step(problem, 0.01, state).status, StepStatus::Ok);
  expectUnitQuaternions(state.configuration);
  // The elastic energy stays a small fraction of the kinetic energy (the linearized step is
  // first-order accurate in the rotation), and every node turned by about 0.25 rad.
  EXPECT_LT(model.energy(state.configuration), 1e-2 * kinetic);
  double mean_angle = 0.0;
  for (int i = 0; i < model.numNodes(); ++i) {
    const double angle =
        Eigen::AngleAxisd(state.configuration.q_TN[i] * layout.rest.q_TN[i].inverse()).angle();
    EXPECT_NEAR(angle, 0.25, 0.03);
    mean_angle += angle / model.numNodes();
  }
  EXPECT_NEAR(mean_angle, 0.25, 0.01);
}

/// Shepard strands and sheets (collinear / coplanar rigid nodes) under gravity, one end clamped.
TEST(RigidNodeQuasiStatic, ShepardCollinearAndCoplanarLayoutsConverge) {
  const Material material = Material::create(5e8, 0.3, 1000.0);
  for (const bool sheet : {false, true}) {
    RigidNodeLayout layout;
    for (int i = 0; i < 10; ++i) {
      for (int j = 0; j < (sheet ? 4 : 1); ++j) {
        layout.rest.p_TN.push_back(Eigen::Vector3d(0.1 * i, 0.0, 0.1 * j));
        layout.rest.q_TN.push_back(Eigen::Quaterniond::Identity());
      }
    }
    std::mt19937 rng(sheet ? 5 : 6);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int num_samples = sheet ? 200 : 50;
    const double thickness = 0.02;
    const double volume = sheet ? 0.9 * 0.3 * thickness : 0.9 * thickness * thickness;
    for (int s = 0; s < num_samples; ++s) {
      RigidNodeSample sample;
      sample.rest_position = Eigen::Vector3d(0.9 * u(rng), thickness * (u(rng) - 0.5),
                                             sheet ? 0.3 * u(rng) : thickness * (u(rng) - 0.5));
      sample.volume = volume / num_samples;
      sample.lambda = material.lambda();
      sample.mu = material.mu();
      sample.density = material.density;
      sample.weights = shepardWeights(layout.rest.p_TN, sample.rest_position, 4, 2.0);
      layout.samples.push_back(sample);
    }
    const RigidNodeModel model(layout.rest, layout.samples);
    EXPECT_NEAR(model.totalVolume(), volume, 1e-12 * volume);
    RigidNodeConfiguration q = layout.rest;
    const StepReport report = solveClampedUnderGravity(model, q);
    EXPECT_EQ(report.status, StepStatus::Ok) << (sheet ? "sheet" : "strand");
    expectUnitQuaternions(q);
    EXPECT_LT(meanDeflection(layout.rest, q, 0.9), -1e-4) << (sheet ? "sheet" : "strand");
  }
}

TEST(RigidNodeSampling, TetMeshLayoutHasFourSamplesPerTetSummingToTheVolume) {
  const TetMesh mesh = makeBeam(1.0, 0.2, 0.1, Eigen::Vector3i(5, 2, 1), ElementType::Tet4);
  const RigidNodeLayout layout = tetMeshLayout(mesh, Material::create(1e8, 0.3, 1000.0));
  ASSERT_EQ(static_cast<int>(layout.samples.size()), 4 * mesh.numElements());
  const RigidNodeModel model(layout.rest, layout.samples);  // validates the partition of unity
  EXPECT_NEAR(model.totalVolume(), 0.02, 1e-14);
  for (const RigidNodeSample& s : layout.samples) EXPECT_EQ(s.weights.nodes.size(), 4u);
  RigidNodeConfiguration q = layout.rest;
  EXPECT_EQ(solveClampedUnderGravity(model, q).status, StepStatus::Ok);
  EXPECT_LT(meanDeflection(layout.rest, q, 1.0), 0.0);
  test::expectInvalidArgument(
      [&] { tetMeshLayout(promoteToTet10(mesh), Material::create(1e4, 0.3, 1000.0)); },
      "needs at least one Tet4 element");
}

TEST(RigidNodeSampling, PoissonDiskLayoutFillsAClosedSurface) {
  const TetMesh box = makeBox(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.4, 0.2, 0.1),
                              Eigen::Vector3i(4, 2, 1), ElementType::Tet4);
  TriMesh surface;
  surface.vertices = box.nodes;
  surface.triangles = extractSurface(box).triangles;
  const Material material = Material::create(1e7, 0.3, 1000.0);
  std::mt19937 rng(42);
  const RigidNodeLayout layout = poissonDiskLayout(surface, 0.07, 0.025, 6, material, rng);
  const RigidNodeModel model(layout.rest, layout.samples);  // validates the partition of unity
  EXPECT_NEAR(model.totalVolume(), 0.008, 1e-15);
  EXPECT_GT(model.numNodes(), 8);
  EXPECT_GT(model.numSamples(), 5 * model.numNodes());
  for (int i = 0; i < model.numNodes(); ++i) {
    const Eigen::Vector3d& p = layout.rest.p_TN[i];
    EXPECT_TRUE((p.array() >= 0.0).all() && (p.array() <= Eigen::Array3d(0.4, 0.2, 0.1)).all());
    for (int j = 0; j < i; ++j) EXPECT_GE((p - layout.rest.p_TN[j]).norm(), 0.07);
  }
  std::mt19937 same(42);
  EXPECT_EQ(poissonDiskLayout(surface, 0.07, 0.025, 6, material, same).rest.p_TN, layout.rest.p_TN);
  // Clamped at its lowest-x nodes, it hangs under gravity.
  RigidNodeProblem problem;
  problem.model = &model;
  problem.body_acceleration = Eigen::Vector3d(0, 0, -9.81);
  for (int i = 0; i < model.numNodes(); ++i)
    if (layout.rest.p_TN[i].x() < 0.1)
      for (int c = 0; c < kRigidNodeDofs; ++c) problem.fixed_dofs.push_back(kRigidNodeDofs * i + c);
  RigidNodeConfiguration q = layout.rest;
  RigidNodeQuasiStatic solver;
  EXPECT_EQ(solver.solve(problem, q).status, StepStatus::Ok);
  expectUnitQuaternions(q);

  test::expectInvalidArgument([&] { poissonDiskLayout(surface, 0.02, 0.025, 6, material, rng); },
                              "node_spacing = 0.02");
  TriMesh open = surface;
  open.triangles.conservativeResize(3, open.triangles.cols() - 1);
  test::expectInvalidArgument([&] { poissonDiskLayout(open, 0.07, 0.025, 6, material, rng); },
                              "not closed");
}

TEST(RigidNodeSolvers, BadProblemsAreRejectedWithTheFieldNamed) {
  Block block;
  RigidNodeConfiguration q = block.layout.rest;
  RigidNodeQuasiStatic solver;
  RigidNodeProblem bad = block.problem;
  bad.fixed_dofs.push_back(block.model.numDofs());
  test::expectInvalidArgument([&] { solver.solve(bad, q); }, "fixed_dofs: 120 is out of range");
  bad = block.problem;
  bad.external_force = Eigen::VectorXd::Zero(7);
  test::expectInvalidArgument([&] { solver.solve(bad, q); }, "external_force has size 7");
  bad = block.problem;
  bad.mass_damping = -1.0;
  test::expectInvalidArgument([&] { solver.solve(bad, q); }, "mass_damping");
  RigidNodeState state;
  state.configuration = q;
  state.velocity = Eigen::VectorXd::Zero(block.model.numDofs());
  RigidNodeImplicitEuler integrator;
  test::expectInvalidArgument([&] { integrator.step(block.problem, 0.0, state); }, "dt");
  test::expectInvalidArgument([] { RigidNodeQuasiStatic({0, 1e-9, 10}); }, "max_iterations = 0");
}

}  // namespace
}  // namespace surgical_sim::core
