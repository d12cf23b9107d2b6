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
  /// The run ended at rest: quasi-static (every step an equilibrium), or a dynamic run whose
  /// last max(2, steps / 10) steps each moved every DOF by at most kSettledStepChange times the
  /// largest displacement from rest (|x_k - x_(k-1)|_inf <= kSettledStepChange |x_N - x_0|_inf).
  bool settled = true;
  /// The reference is an equilibrium (tip_displacement, uniaxial_svk_force), so only a settled
  /// run can be compared with it; a self_reference run is compared step for step.
  bool static_reference = false;
  /// uniaxial_svk_force only: stretch l [-], measured and exact force [N] at each load factor.
  std::vector<double> path_stretch, path_force, path_exact;
};

/// Bound on the last steps' position change, relative to the displacement, for a dynamic run to
/// count as settled (CaseResult::settled) [-].
inline constexpr double kSettledStepChange = 1e-4;

/// All cases of a scene's sweep, in a stable order. Models that only support linear tets
/// (mass_spring, ems) are skipped for tet10.
std::vector<CaseSpec> expandSweep(const BenchmarkScene& scene);

/// The runtime scene of one case (what TissueSimulation runs for it): the shared keys of
/// `scene` with the case's resolution, element type, model, integrator and solver.
RuntimeScene caseScene(const BenchmarkScene& scene, const CaseSpec& spec);

/// Runs one case headless and measures it against the scene's reference.
/// @throws std::invalid_argument when the scene and case do not fit (e.g. an empty BC region).
CaseResult runTissueCase(const BenchmarkScene& scene, const CaseSpec& spec);

/// Label of a case in reports: "<scene name>_<element type>_<resolution x>x<y>x<z>" for a
/// generated mesh, "<scene name>_<element type>_<file stem>" for a mesh file.
std::string caseLabel(const BenchmarkScene& scene, const CaseSpec& spec);

/// Status of a case in reports: "unsettled" when its steps were ok but it did not settle against
/// a static reference (its error then measures the motion, not the accuracy), else the name of
/// CaseResult::status.
std::string caseStatus(const CaseResult& result);

/// CSV header of tissue_bench rows:
/// case,model,integrator,solver,nodes,elements,dofs,dt,ms_per_step,steps,error_rel,settled,status
const char* caseCsvHeader();
/// One CSV row (no newline) for `result`, labelled `label` (caseLabel()).
std::string caseCsvRow(const std::string& label, const CaseResult& result);

}  // namespace surgical_sim::bench
