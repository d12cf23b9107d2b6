// T4 (BENCHMARKS.md): the large-deflection soft cantilever of config/bench/t4_soft_cantilever.yaml
// with the meshless efg model, against the converged tet10 corotational answer that the file
// names as its reference.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "surgical_sim/bench/tissue_case.h"
#include "surgical_sim/core/scene/scene_build.h"
#include "surgical_sim/core/scene/tissue_simulation.h"
#include "surgical_sim/core/tissue/efg_model.h"

namespace surgical_sim::bench {
namespace {

/// Mean tip displacement [m] of one efg case: the model interpolated at the mesh nodes of the
/// scene's measure region (as tissue_bench measures it), all three components.
Eigen::Vector3d efgTipDisplacement(const BenchmarkScene& scene, const CaseSpec& spec) {
  TissueSimulation sim(caseScene(scene, spec));
  const auto& efg = dynamic_cast<const EfgModel&>(sim.model());
  // The particle grid is mirror-symmetric about y = 0 (the spacings divide the width).
  const Eigen::Matrix3Xd& particles = efg.grid().particles;
  for (Eigen::Index a = 0; a < particles.cols(); ++a) {
    const Eigen::Vector3d mirror(particles(0, a), -particles(1, a), particles(2, a));
    EXPECT_LT((particles.colwise() - mirror).colwise().norm().minCoeff(), 1e-12) << a;
  }
  const SimulationStepStats stats = sim.step();
  EXPECT_EQ(stats.report.status, StepStatus::Ok);
  const Eigen::Map<const Eigen::VectorXd> nodes(sim.mesh().nodes.data(), sim.mesh().nodes.size());
  const std::vector<int> dofs = regionDofs(nodes, scene.measure.region, Eigen::Vector3i(1, 0, 0));
  Eigen::Matrix3Xd tip(3, static_cast<Eigen::Index>(dofs.size()));
  for (std::size_t i = 0; i < dofs.size(); ++i)
    tip.col(static_cast<Eigen::Index>(i)) = sim.mesh().nodes.col(dofs[i] / 3);
  const Eigen::SparseMatrix<double> W = efg.interpolation(tip);
  const Eigen::VectorXd u = sim.state().x - efg.restPositions();
  const Eigen::Map<const Eigen::Matrix3Xd> u_particles(u.data(), 3, u.size() / 3);
  return (u_particles * W.transpose()).rowwise().mean();
}

TEST(T4SoftCantilever, EfgConvergesToTheTet10AnswerInThePlaneOfTheLoad) {
  const BenchmarkScene scene = loadBenchmarkScene(std::string(SURGICAL_SIM_SOURCE_DIR) +
                                                  "/config/bench/t4_soft_cantilever.yaml");
  ASSERT_TRUE(scene.measure.reference.has_value());
  const double reference = *scene.measure.reference;  // tet10, finest mesh [m]
  const double length = scene.mesh.size.x();
  // The three coarsest efg grids (d = 5, 2.5, 1.67 mm); the finest (1.25 mm) is left to the bench.
  std::vector<double> errors;
  for (const CaseSpec& spec : expandSweep(scene)) {
    if (spec.model != ModelKind::Efg || errors.size() == 3) continue;
    const Eigen::Vector3d u = efgTipDisplacement(scene, spec);
    errors.push_back(std::abs(u.z() - reference) / std::abs(reference));
    RecordProperty("tip_error_" + std::to_string(errors.size()), std::to_string(errors.back()));
    // Large deformation: the tip moves down by more than 20 % of the length.
    EXPECT_LT(u.z(), -0.2 * length);
    // Mirror-symmetric beam, grid and load: the tip stays in the plane y = 0 of the load.
    EXPECT_LE(std::abs(u.y()) / std::abs(u.z()), 1e-6);
  }
  // Measured: 16.9 %, 3.9 %, 1.7 % (and 0.96 % at d = 1.25 mm in the bench), all on the soft
  // side, falling as d^2 (error ratios 2.3 and 1.8 for spacing ratios 1.5 and 1.33): the
  // extrapolated efg tip agrees with tet10 within 0.1 %. The bound leaves 15 % of the finest
  // error for round-off and platform differences.
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_LT(errors[1], 0.5 * errors[0]);
  EXPECT_LT(errors[2], 0.5 * errors[1]);
  EXPECT_LT(errors[2], 0.02);
}

}  // namespace
}  // namespace surgical_sim::bench
