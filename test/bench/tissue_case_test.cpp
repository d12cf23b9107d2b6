#include "surgical_sim/bench/tissue_case.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "surgical_sim/core/scene/scene_build.h"
#include "surgical_sim/core/scene/scene_config.h"

namespace surgical_sim::bench {
namespace {

/// A 1-cell box clamped at z = 0, measured against its own tight reference, with `loads` (extra
/// YAML lines, e.g. gravity) appended.
BenchmarkScene selfReferencedBox(const std::string& name, const std::string& loads) {
  return parseBenchmarkScene("name: " + name + R"(
mesh: {generator: box, size: [0.05, 0.05, 0.05], resolutions: [[1, 1, 1]]}
material: {young_modulus: 20.0e3, poisson_ratio: 0.3, density: 1000.0}
models: corotational
integrators: implicit_euler_linearized
solvers: cholmod
time_step: 0.01
steps: 2
fixed:
  - region: {max: [.inf, .inf, 1.0e-9]}
measure: {type: self_reference}
)" + loads,
                             name + ".yaml");
}

/// A 0.1 m corotational cantilever (4 x 1 x 1 cells) sagging under gravity, measured against the
/// static Euler-Bernoulli + Timoshenko tip deflection, run with `integrator` for `steps` steps of
/// `dt` [s].
BenchmarkScene saggingCantilever(const std::string& integrator, double dt, int steps) {
  return parseBenchmarkScene(R"(
name: sag
mesh: {generator: beam, size: [0.1, 0.02, 0.02], resolutions: [[4, 1, 1]]}
material: {young_modulus: 1.0e6, poisson_ratio: 0.3, density: 1000.0}
models: corotational
integrators: )" + integrator + R"(
solvers: cholmod
time_step: )" + std::to_string(dt) +
                                 R"(
steps: )" + std::to_string(steps) +
                                 R"(
gravity: [0, 0, -9.81]
fixed: [{region: {max: [1.0e-9, .inf, .inf]}}]
measure: {type: tip_displacement, region: {min: [0.099999999, -.inf, -.inf]}, component: z,
          reference_formula: euler_bernoulli_timoshenko}
)",
                             "sag.yaml");
}

TEST(TissueCase, DynamicRunStoppedEarlyIsFlaggedUnsettled) {
  // Three 1 ms steps: the beam is still falling, far from the static reference.
  const BenchmarkScene scene = saggingCantilever("implicit_euler_linearized", 0.001, 3);
  const CaseResult r = runTissueCase(scene, expandSweep(scene).front());
  EXPECT_EQ(r.status, StepStatus::Ok);
  EXPECT_TRUE(r.static_reference);
  EXPECT_FALSE(r.settled);
  EXPECT_EQ(caseStatus(r), "unsettled");
  const std::string row = caseCsvRow(caseLabel(scene, r.spec), r);
  EXPECT_EQ(row.substr(row.size() - std::string(",0,unsettled").size()), ",0,unsettled") << row;
}

TEST(TissueCase, DynamicRunAtRestAndQuasiStaticRunAreSettled) {
  // 1 s implicit Euler steps damp the beam's modes (periods of milliseconds) within a few steps.
  const BenchmarkScene dynamic = saggingCantilever("implicit_euler_linearized", 1.0, 30);
  const CaseResult d = runTissueCase(dynamic, expandSweep(dynamic).front());
  EXPECT_TRUE(d.settled);
  EXPECT_EQ(caseStatus(d), "ok");
  const BenchmarkScene quasi_static = saggingCantilever("quasi_static", 1.0, 1);
  const CaseResult q = runTissueCase(quasi_static, expandSweep(quasi_static).front());
  EXPECT_TRUE(q.settled);
  EXPECT_EQ(caseStatus(q), "ok");
  // Both runs end at the same equilibrium.
  EXPECT_NEAR(d.measured, q.measured, 1e-4 * std::abs(q.measured));
  const std::string row = caseCsvRow(caseLabel(dynamic, d.spec), d);
  EXPECT_EQ(row.substr(row.size() - std::string(",1,ok").size()), ",1,ok") << row;
}

TEST(TissueCase, CsvRowHasOneFieldPerHeaderColumn) {
  const BenchmarkScene scene = saggingCantilever("quasi_static", 1.0, 1);
  const std::string row = caseCsvRow("label", runTissueCase(scene, expandSweep(scene).front()));
  const std::string header = caseCsvHeader();
  EXPECT_EQ(std::count(row.begin(), row.end(), ','), std::count(header.begin(), header.end(), ','))
      << header << "\n"
      << row;
}

TEST(TissueCase, LabelNamesTheResolutionOrTheMeshFile) {
  BenchmarkScene scene = saggingCantilever("quasi_static", 1.0, 1);
  const CaseSpec spec = expandSweep(scene).front();
  EXPECT_EQ(caseLabel(scene, spec), "sag_tet4_4x1x1");
  scene.mesh.generator = "file";
  scene.mesh.file = "/data/meshes/liver_coarse.msh";
  EXPECT_EQ(caseLabel(scene, spec), "sag_tet4_liver_coarse");
}

TEST(TissueCase, RelativeErrorAgainstAZeroReferenceIsNaN) {
  // No gravity, no prescribed motion: the self reference does not move, so a relative error
  // against it is meaningless (it printed as 5e282 with status ok).
  const BenchmarkScene scene = selfReferencedBox("unloaded", "");
  const std::vector<CaseSpec> cases = expandSweep(scene);
  ASSERT_EQ(cases.size(), 1u);
  const CaseResult r = runTissueCase(scene, cases.front());
  EXPECT_EQ(r.reference, 0.0);
  EXPECT_TRUE(std::isnan(r.error_rel)) << r.error_rel;
  EXPECT_NE(caseCsvRow("unloaded", r).find(",nan,"), std::string::npos)
      << caseCsvRow("unloaded", r);
}

TEST(TissueCase, LoadedSelfReferenceHasFiniteError) {
  const BenchmarkScene scene = selfReferencedBox("sagging", "gravity: [0, 0, -9.81]\n");
  const CaseResult r = runTissueCase(scene, expandSweep(scene).front());
  EXPECT_GT(r.reference, 0.0);
  EXPECT_TRUE(std::isfinite(r.error_rel));
  EXPECT_LT(r.error_rel, 1.0);
}

TEST(TissueCase, LinearizedRunReportsItsPhasesRatesAndMemory) {
  const BenchmarkScene scene = selfReferencedBox("sagging", "gravity: [0, 0, -9.81]\n");
  const CaseResult r = runTissueCase(scene, expandSweep(scene).front());
  ASSERT_EQ(r.status, StepStatus::Ok);
  // Each step's phases are disjoint parts of it, so their means are at most the mean step.
  EXPECT_GT(r.phases.forces, 0.0);
  EXPECT_GT(r.phases.factorization, 0.0);
  EXPECT_LE(1e3 * r.phases.sum(), r.ms_per_step);
  EXPECT_GT(r.first_step_ms, 0.0);
  EXPECT_GE(r.ms_p99, r.ms_per_step);          // two steps: the p99 is the slower one
  EXPECT_DOUBLE_EQ(r.linear_iterations, 1.0);  // one direct solve per step
  EXPECT_GT(r.peak_rss_bytes, 1e6);
  for (const double rate :
       {r.rates.forces_gflops, r.rates.forces_gbs, r.rates.assembly_gbs,
        r.rates.factorization_gflops, r.rates.solve_gflops, r.rates.solve_gbs}) {
    EXPECT_TRUE(std::isfinite(rate));
    EXPECT_GT(rate, 0.0);
  }
  const std::string row = caseCsvRow("sagging", r, "after");
  EXPECT_EQ(row.rfind("sagging,after,corotational,", 0), 0u) << row;
}

TEST(TissueCase, NewtonRunHasNoRateEstimates) {
  const BenchmarkScene scene = saggingCantilever("implicit_euler_newton", 0.01, 1);
  const CaseResult r = runTissueCase(scene, expandSweep(scene).front());
  EXPECT_GT(r.phases.forces, 0.0);
  EXPECT_TRUE(std::isnan(r.rates.forces_gflops));
  EXPECT_TRUE(std::isnan(r.rates.solve_gbs));
}

TEST(TissueCase, PrecomputedSelfReferenceGivesTheSameError) {
  const BenchmarkScene scene = selfReferencedBox("sagging", "gravity: [0, 0, -9.81]\n");
  const CaseSpec spec = expandSweep(scene).front();
  const CaseResult computed = runTissueCase(scene, spec);
  const Eigen::VectorXd x_ref = selfReferencePositions(scene, spec);
  const CaseResult given = runTissueCase(scene, spec, &x_ref);
  EXPECT_DOUBLE_EQ(given.error_rel, computed.error_rel);
  EXPECT_DOUBLE_EQ(given.reference, computed.reference);
  const Eigen::VectorXd short_ref = x_ref.head(3);
  EXPECT_THROW(runTissueCase(scene, spec, &short_ref), std::invalid_argument);
  const Eigen::VectorXd no_ref;  // the reference run failed
  const CaseResult unmeasured = runTissueCase(scene, spec, &no_ref);
  EXPECT_TRUE(std::isnan(unmeasured.error_rel));
  EXPECT_EQ(unmeasured.status, StepStatus::Ok);
  EXPECT_GT(unmeasured.ms_per_step, 0.0);
  EXPECT_EQ(selfReferenceKey(scene, spec), "sagging_tet4_1x1x1/corotational/dynamic");
}

TEST(TissueCase, VariantsChangingOnlyTheSolversShareTheReference) {
  const BenchmarkScene scene = selfReferencedBox("box", R"(
variants:
  - name: before
  - name: after
    solvers: [pcg_cholesky_reuse]
    pcg: {tolerance: 1.0e-8}
    contact: {full_delassus: true}
    threads: 2
    mesh: {resolutions: [[1, 1, 1], [2, 1, 1]]}
  - name: stiffer
    material: {young_modulus: 40.0e3}
)");
  const std::vector<BenchmarkVariant> variants = benchVariants(scene);
  ASSERT_EQ(variants.size(), 3u);
  EXPECT_EQ(referenceGroup(variants[0]), "");
  EXPECT_EQ(referenceGroup(variants[1]), "");
  EXPECT_EQ(referenceGroup(variants[2]), "stiffer");
}

TEST(TissueCase, ScenesWithoutVariantsRunAsOneUnnamedVariant) {
  const BenchmarkScene scene = selfReferencedBox("plain", "");
  const std::vector<BenchmarkVariant> variants = benchVariants(scene);
  ASSERT_EQ(variants.size(), 1u);
  EXPECT_EQ(variants.front().name, "");
  EXPECT_EQ(variants.front().scene.name, "plain");
}

TEST(TissueCase, MeshBeyondTheBudgetIsRejectedBeforeBuilding) {
  MeshSpec spec;
  spec.generator = "box";
  spec.size = Eigen::Vector3d::Constant(0.1);
  try {
    buildSceneMesh(spec, Eigen::Vector3i::Constant(4096), ElementType::Tet10);
    FAIL() << "a 4096^3 tet10 box was built";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("key 'mesh.resolution'"), std::string::npos) << e.what();
  }
}

TEST(TissueCase, BadMeshFileIsNamedWithTheKey) {
  // Two tets sharing a face, the second one inverted (its last two nodes swapped).
  const std::string path = ::testing::TempDir() + "/inverted_two_tets.msh";
  std::ofstream(path) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n"
                         "2 10 0 0\n3 0 10 0\n4 0 0 10\n5 10 10 10\n$EndNodes\n$Elements\n2\n"
                         "1 4 0 1 2 3 4\n2 4 0 2 3 5 4\n$EndElements\n";
  MeshSpec spec;
  spec.generator = "file";
  spec.file = path;
  spec.metres_per_unit = 1e-3;
  try {
    buildSceneMesh(spec, Eigen::Vector3i::Zero(), ElementType::Tet4);
    FAIL() << "an inverted mesh was built";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("key 'mesh.file': " + path + ": invalid mesh"), std::string::npos)
        << message;
    EXPECT_NE(message.find("inverted"), std::string::npos) << message;
  }
  spec.file = ::testing::TempDir() + "/no_such_mesh.msh";
  try {
    buildSceneMesh(spec, Eigen::Vector3i::Zero(), ElementType::Tet4);
    FAIL() << "a missing mesh was built";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("key 'mesh.file': " + spec.file + ": cannot open"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace surgical_sim::bench
