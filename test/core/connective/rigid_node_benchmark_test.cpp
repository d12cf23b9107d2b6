// Bosman's validation cases for the rigid-node model (BENCHMARKS.md T1 / T5a and T5c).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "surgical_sim/core/connective/rigid_node_quasi_static.h"
#include "surgical_sim/core/connective/rigid_node_sampling.h"

namespace surgical_sim::core {
namespace {

/// T1 steel cantilever 16 x 0.5 x 0.5 m under self-weight with 25 rigid nodes along its length
/// (trilinear weights, 8 neighbours), clamped at x = 0: tip deflection of the rigid nodes at
/// x = 16 m.
double cantileverTipDeflection(int cross_section_nodes, int gauss_points) {
  const RigidNodeLayout layout =
      trilinearGridLayout(Eigen::Vector3d(0, -0.25, -0.25), Eigen::Vector3d(16.0, 0.5, 0.5),
                          Eigen::Vector3i(25, cross_section_nodes, cross_section_nodes),
                          gauss_points, Material::create(200e9, 0.3, 7800.0));
  const RigidNodeModel model(layout.rest, layout.samples);
  RigidNodeProblem problem;
  problem.model = &model;
  problem.body_acceleration = Eigen::Vector3d(0, -9.81, 0);
  for (int i = 0; i < model.numNodes(); ++i)
    if (layout.rest.p_TN[i].x() == 0.0)
      for (int c = 0; c < kRigidNodeDofs; ++c) problem.fixed_dofs.push_back(kRigidNodeDofs * i + c);
  RigidNodeConfiguration q = layout.rest;
  RigidNodeQuasiStatic solver;
  const StepReport report = solver.solve(problem, q);
  EXPECT_EQ(report.status, StepStatus::Ok);
  double sum = 0.0;
  int count = 0;
  for (int i = 0; i < model.numNodes(); ++i) {
    if (layout.rest.p_TN[i].x() < 16.0) continue;
    sum += q.p_TN[i].y() - layout.rest.p_TN[i].y();
    ++count;
  }
  return -sum / count;
}

TEST(RigidNodeBenchmarks, T1SteelCantileverWith25RigidNodesAlongTheLength) {
  const double reference = 0.1501;  // m, BENCHMARKS.md T1 (fine quadratic hex FE)
  for (int nodes : {2, 3}) {
    const double tip = cantileverTipDeflection(nodes, 2);
    std::printf("T1 rigid nodes 25 x %d x %d: tip %.5f m, error %+.2f %%\n", nodes, nodes, tip,
                100.0 * (tip - reference) / reference);
  }
}

}  // namespace
}  // namespace surgical_sim::core
