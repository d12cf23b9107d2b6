// Bosman's validation cases for the rigid-node model (BENCHMARKS.md T1 / T5a and T5c).

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "surgical_sim/core/connective/rigid_node_quasi_static.h"
#include "surgical_sim/core/connective/rigid_node_sampling.h"

namespace surgical_sim::core {
namespace {

/// T1 steel cantilever 16 x 0.5 x 0.5 m under self-weight with 25 rigid nodes along its length
/// and 7 x 7 across (trilinear weights, 8 neighbours), clamped at x = 0: the mean deflection of
/// the rigid nodes at x = 16 m is within 1 % of the fine FE answer (the cross-section
/// convergence table is in docs/models.md).
TEST(RigidNodeBenchmarks, T1SteelCantileverWith25RigidNodesAlongTheLength) {
  const double reference = 0.1501;  // m, BENCHMARKS.md T1 (fine quadratic hex FE)
  const RigidNodeLayout layout =
      trilinearGridLayout(Eigen::Vector3d(0, -0.25, -0.25), Eigen::Vector3d(16.0, 0.5, 0.5),
                          Eigen::Vector3i(25, 7, 7), Material::create(200e9, 0.3, 7800.0));
  const RigidNodeModel model(layout.rest, layout.samples);
  EXPECT_NEAR(model.totalMass(), 31200.0, 1e-6);
  RigidNodeProblem problem;
  problem.model = &model;
  problem.body_acceleration = Eigen::Vector3d(0, -9.81, 0);
  for (int i = 0; i < model.numNodes(); ++i)
    if (layout.rest.p_TN[i].x() == 0.0)
      for (int c = 0; c < kRigidNodeDofs; ++c) problem.fixed_dofs.push_back(kRigidNodeDofs * i + c);
  RigidNodeConfiguration q = layout.rest;
  RigidNodeNewtonSettings settings;
  settings.relative_tolerance = 1e-6;
  RigidNodeQuasiStatic solver(settings);
  ASSERT_EQ(solver.solve(problem, q).status, StepStatus::Ok);
  double sum = 0.0;
  int count = 0;
  for (int i = 0; i < model.numNodes(); ++i) {
    if (layout.rest.p_TN[i].x() < 16.0) continue;
    sum += q.p_TN[i].y() - layout.rest.p_TN[i].y();
    ++count;
  }
  const double tip = -sum / count;
  std::printf("T1 rigid nodes 25 x 7 x 7: tip %.5f m, error %+.2f %%\n", tip,
              100.0 * (tip - reference) / reference);
  EXPECT_NEAR(tip, reference, 0.01 * reference);
}

/// Trilinear weights of rest point p in the grid of cells (origin, spacing [m]) whose corner
/// rigid nodes are found by their rest positions.
SampleWeights gridPointWeights(const RigidNodeConfiguration& rest, const Eigen::Vector3d& origin,
                               const Eigen::Vector3d& spacing, const Eigen::Vector3i& cells,
                               const Eigen::Vector3d& p) {
  const Eigen::Vector3i cell = (p - origin)
                                   .cwiseQuotient(spacing)
                                   .cast<int>()
                                   .cwiseMin(cells - Eigen::Vector3i::Ones())
                                   .cwiseMax(Eigen::Vector3i::Zero());
  std::array<int, 8> nodes;
  nodes.fill(-1);
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3i corner = cell + Eigen::Vector3i(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    const Eigen::Vector3d position = origin + spacing.cwiseProduct(corner.cast<double>());
    for (int i = 0; i < rest.numNodes(); ++i)
      if ((rest.p_TN[i] - position).norm() < 1e-9) nodes[c] = i;
  }
  return trilinearWeights(nodes, origin + spacing.cwiseProduct(cell.cast<double>()), spacing, p);
}

/// T5(c) traction: a 6 m x 1 m diameter cylinder along x (trilinear weights, 8 neighbours,
/// samples inside the cylinder) stretched 3 mm: the rigid nodes of both end faces held along x
/// (the far ones displaced) and in their rotations about y and z (the faces stay plane, as in
/// the uniaxial solution, where every rigid node keeps its orientation), free laterally; the
/// rigid modes removed at the centre of the near face. The surface contracts by nu eps r.
TEST(RigidNodeBenchmarks, T5cCylinderTractionContractsLaterallyByNuEpsR) {
  const double length = 6.0, radius = 0.5, stretch = 0.003, nu = 0.3;
  const RigidNodeLayout layout = trilinearGridLayout(
      Eigen::Vector3d(0, -radius, -radius), Eigen::Vector3d(length, 2 * radius, 2 * radius),
      Eigen::Vector3i(13, 5, 5), Material::create(210e9, nu, 7800.0),
      [&](const Eigen::Vector3d& p) { return p.y() * p.y() + p.z() * p.z() <= radius * radius; },
      M_PI * radius * radius * length);
  const RigidNodeModel model(layout.rest, layout.samples);
  EXPECT_NEAR(model.totalVolume(), M_PI * radius * radius * length, 1e-9);
  RigidNodeProblem problem;
  problem.model = &model;
  RigidNodeConfiguration q = layout.rest;
  for (int i = 0; i < model.numNodes(); ++i) {
    const Eigen::Vector3d& p = layout.rest.p_TN[i];
    if (p.x() == 0.0 || p.x() == length)
      for (int c : {0, 4, 5}) problem.fixed_dofs.push_back(kRigidNodeDofs * i + c);
    if (p.x() == length) q.p_TN[i].x() += stretch;
    if (p.x() == 0.0 && p.y() == 0.0 && p.z() == 0.0)
      for (int c : {1, 2, 3}) problem.fixed_dofs.push_back(kRigidNodeDofs * i + c);
  }
  RigidNodeQuasiStatic solver;
  ASSERT_EQ(solver.solve(problem, q).status, StepStatus::Ok);
  const Eigen::Vector3d origin(0, -radius, -radius), spacing(0.5, 0.25, 0.25);
  const Eigen::Vector3i cells(12, 4, 4);
  // Surface points A, B, C at mid-length and at the quarter points, on the y and z axes.
  const double expected = -nu * (stretch / length) * radius;
  for (const double x : {1.5, 3.0, 4.5}) {
    for (const Eigen::Vector3d& direction : {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, -1)}) {
      const Eigen::Vector3d rest_point = Eigen::Vector3d(x, 0, 0) + radius * direction;
      const SampleWeights w = gridPointWeights(layout.rest, origin, spacing, cells, rest_point);
      const Eigen::Vector3d u = model.mapPoint(q, w, rest_point) - rest_point;
      const double lateral = u.dot(direction);
      std::printf("T5c point x %.1f m, direction (%g, %g): lateral %.4e m, expected %.4e m\n", x,
                  direction.y(), direction.z(), lateral, expected);
      EXPECT_NEAR(lateral, expected, 0.01 * std::abs(expected));
    }
  }
}

}  // namespace
}  // namespace surgical_sim::core
