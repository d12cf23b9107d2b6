#include "surgical_sim/bench/cut_fuzz.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "surgical_sim/core/cutting/cut_mesh_check.h"
#include "surgical_sim/core/cutting/cut_tissue_model.h"
#include "surgical_sim/core/cutting/tet_cutter.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/mesh_check.h"
#include "surgical_sim/core/mesh/surface.h"
#include "surgical_sim/core/mesh/surface_closure.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

CutFuzzReport runCutFuzz(const CutFuzzSettings& settings) {
  if (settings.sweeps < 1)
    throw std::invalid_argument("runCutFuzz: sweeps = " + std::to_string(settings.sweeps) +
                                " must be >= 1");
  const Eigen::Vector3d semi = settings.semi_axes;
  TetCutter cutter(makeOrganBlob(semi, settings.cells_per_axis, ElementType::Tet4), 1000.0);
  const double mass = cutter.lumpedMass().sum();
  std::mt19937 rng(settings.seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto point = [&] {
    return Eigen::Vector3d(semi.x() * u(rng), semi.y() * u(rng), semi.z() * u(rng));
  };
  CutFuzzReport report;
  report.min_rest_volume = INFINITY;
  for (int i = 0; i < settings.sweeps && report.failure.empty(); ++i) {
    BladeSweep sweep;
    sweep.start.resize(3, 3);
    sweep.end.resize(3, 3);
    const Eigen::Vector3d motion = 0.5 * point();
    for (int k = 0; k < 3; ++k) {
      sweep.start.col(k) = point();
      sweep.end.col(k) = sweep.start.col(k) + motion;
    }
    const TetMesh& mesh = cutter.mesh();
    const Eigen::VectorXd x0 =
        Eigen::Map<const Eigen::VectorXd>(mesh.nodes.data(), 3 * mesh.numNodes());
    Eigen::VectorXd x1 = x0;
    const Eigen::Vector3d shift = 0.005 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    for (int v = 0; v < mesh.numNodes(); ++v) x1.segment<3>(3 * v) += shift;
    const CutUpdate update = cutter.cut(sweep, x0, x1);
    const double ms = 1e3 * (update.detect_seconds + update.update_seconds);
    report.mean_update_ms += ms / settings.sweeps;
    report.max_update_ms = std::max(report.max_update_ms, ms);
    report.sweeps = i + 1;
    const Eigen::VectorXd& m = cutter.lumpedMass();
    report.finite = report.finite && m.allFinite();
    report.max_mass_error = std::max(report.max_mass_error, std::abs(m.sum() - mass) / mass);
    for (int e = 0; e < cutter.mesh().numElements(); ++e)
      report.min_rest_volume = std::min(report.min_rest_volume, signedVolume(cutter.mesh(), e));
    std::string problem = cutMeshProblem(cutter.mesh());
    if (problem.empty() &&
        (cutter.surface().triangles.cols() != extractSurface(cutter.mesh()).triangles.cols() ||
         checkSurfaceClosure(cutter.surface().triangles).open_edges > 0))
      problem = "the cutter's surface differs from the mesh boundary";
    if (problem.empty() && !(m.array() > 0.0).all()) problem = "a node has no mass";
    if (problem.empty() && !(report.max_mass_error <= 1e-12)) problem = "mass not conserved";
    if (problem.empty() && !(report.min_rest_volume > 0.0)) problem = "non-positive element volume";
    if (!problem.empty()) report.failure = "sweep " + std::to_string(i) + ": " + problem;
  }
  report.cut_edges = cutter.numCutEdges();
  report.components = cutter.numComponents();
  report.pinched_edges = checkSurfaceClosure(cutter.surface().triangles).pinched_edges;

  const auto model =
      makeCutTissueModel(ModelKind::Corotational, cutter, Material::create(5e3, 0.45, 1000.0));
  DynamicsProblem problem;
  problem.model = model.get();
  problem.external_force = model->bodyForce(Eigen::Vector3d(0, 0, -9.81));
  SimulationState state{model->restPositions(),
                        Eigen::VectorXd::Zero(model->restPositions().size()), 0.0};
  const auto integrator = makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {},
                                         makeLinearSolver(SolverKind::Cholmod, {}));
  for (int i = 0; i < settings.simulate_steps; ++i) {
    const StepStatus s = integrator->step(problem, 0.01, state).status;
    if (s != StepStatus::Ok && s != StepStatus::NotConverged && report.failure.empty())
      report.failure = "simulation step " + std::to_string(i) + ": " + toString(s);
  }
  report.finite = report.finite && state.x.allFinite();
  return report;
}

}  // namespace surgical_sim::bench
