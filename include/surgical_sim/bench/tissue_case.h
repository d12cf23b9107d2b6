#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/scene/scene_config.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

/// One point of a scene's sweep: resolution x element type x model x integrator x solver.
struct CaseSpec {
  Eigen::Vector3i resolution = Eigen::Vector3i::Zero();
  ElementType element_type = ElementType::Tet4;
  ModelKind model = ModelKind::Corotational;
  IntegratorKind integrator = IntegratorKind::ImplicitEulerLinearized;
  SolverKind solver = SolverKind::Cholmod;
};

/// Measured outcome of one case; one CSV row of tissue_bench.
struct CaseResult {
  CaseSpec spec;
  int nodes = 0;     ///< model nodes (efg: particles)
  int elements = 0;  ///< mesh elements (efg: integration points)
  int dofs = 0;
  double dt = 0.0;                     ///< [s]
  double ms_per_step = 0.0;            ///< mean wall time of one integrator step [ms]
  int steps = 0;                       ///< integrator steps taken
  double measured = 0.0;               ///< measured quantity (tip displacement [m] or force [N])
  double reference = 0.0;              ///< its reference value
  double error_rel = 0.0;              ///< relative error [-]; NaN when the case failed or the
                                       ///< reference is zero or non-finite
  StepStatus status = StepStatus::Ok;  ///< first non-Ok status, or Ok
  /// uniaxial_svk_force only: stretch l [-], measured and exact force [N] at each load factor.
  std::vector<double> path_stretch, path_force, path_exact;
};

/// All cases of a scene's sweep, in a stable order. Models that only support linear tets
/// (mass_spring, ems) are skipped for tet10.
std::vector<CaseSpec> expandSweep(const BenchmarkScene& scene);

/// The runtime scene of one case (what TissueSimulation runs for it): the shared keys of
/// `scene` with the case's resolution, element type, model, integrator and solver.
RuntimeScene caseScene(const BenchmarkScene& scene, const CaseSpec& spec);

/// Runs one case headless and measures it against the scene's reference.
/// @throws std::invalid_argument when the scene and case do not fit (e.g. an empty BC region).
CaseResult runTissueCase(const BenchmarkScene& scene, const CaseSpec& spec);

/// CSV header of tissue_bench rows.
const char* caseCsvHeader();
/// One CSV row (no newline) for `result` of scene `scene_name`.
std::string caseCsvRow(const std::string& scene_name, const CaseResult& result);

}  // namespace surgical_sim::bench
