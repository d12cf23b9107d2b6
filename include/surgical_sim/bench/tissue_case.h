#pragma once

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/scene/scene_config.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

/// A rate that was not estimated.
inline constexpr double kNoRate = std::numeric_limits<double>::quiet_NaN();

/// One point of a scene's sweep: resolution x element type x model x integrator x solver.
struct CaseSpec {
  Eigen::Vector3i resolution = Eigen::Vector3i::Zero();
  ElementType element_type = ElementType::Tet4;
  ModelKind model = ModelKind::Corotational;
  IntegratorKind integrator = IntegratorKind::ImplicitEulerLinearized;
  SolverKind solver = SolverKind::Cholmod;
};

/// Achieved throughput of the phases of a run [GFLOP/s], [GB/s]; NaN where not estimated.
struct PhaseRates {
  double forces_gflops = kNoRate, forces_gbs = kNoRate;
  double assembly_gflops = kNoRate, assembly_gbs = kNoRate;
  double factorization_gflops = kNoRate, factorization_gbs = kNoRate;
  double solve_gflops = kNoRate, solve_gbs = kNoRate;
};

/// Measured outcome of one case; one CSV row of tissue_bench.
struct CaseResult {
  CaseSpec spec;
  int nodes = 0;     ///< model nodes (efg: particles)
  int elements = 0;  ///< mesh elements (efg: integration points)
  int dofs = 0;
  double dt = 0.0;              ///< [s]
  double ms_per_step = 0.0;     ///< mean wall time of one integrator step [ms]
  int steps = 0;                ///< integrator steps taken
  double ms_p99 = 0.0;          ///< 99th percentile of the step wall times [ms]
  double first_step_ms = 0.0;   ///< the first step (pattern analysis, first factor) [ms]
  double ms_after_first = 0.0;  ///< mean of the steps after the first [ms] (0: one step)
  /// Mean per step of the integrator's phase times (StepReport::phases) [s].
  StepPhaseTimes phases;
  double linear_iterations = 0.0;  ///< mean linear iterations per step (1 per direct solve)
  /// Peak resident memory of the process when the run ended, before the reference run
  /// (peakResidentBytes()) [bytes]: the case's own peak when it runs in a fresh process.
  double peak_rss_bytes = 0.0;
  /// Achieved throughput of each phase: estimated work (estimateStepWork()) over its time.
  /// implicit_euler_linearized only (one force evaluation, assembly and factorization per step;
  /// factorization: cholmod only); NaN otherwise.
  PhaseRates rates;
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

/// Tolerance of the self_reference run: Newton's relative residual and, for an iterative
/// measure.reference_solver, each CG solve's (with the sized iteration cap) [-].
inline constexpr double kReferenceTolerance = 1e-10;
/// Newton iteration limit of the self_reference run [-].
inline constexpr int kReferenceNewtonIterations = 50;

/// `scene` with the tolerances of its self_reference run (kReferenceTolerance).
BenchmarkScene tightReferenceScene(const BenchmarkScene& scene);

/// 99th percentile of `values` (the ceil(0.99 n)-th smallest); 0 for none.
double percentile99(std::vector<double> values);

/// The configurations a bench runs for `scene`: its variants, or the scene itself (named "").
std::vector<BenchmarkVariant> benchVariants(const BenchmarkScene& scene);

/// Sets SURGICAL_SIM_THREADS to scene.threads when the scene gives it (thread count of the
/// element loops and triangular solves). Changes this process's environment: call it in the
/// process that runs the case (the benches' child), before building anything.
void applyBenchThreads(const BenchmarkScene& scene);

/// Name of the reference group of `variant`: "" when the variant sets only keys that leave the
/// tight reference runs unchanged (solvers, integrators, models, pcg.*, newton.*, threads,
/// mesh.resolutions, mesh.element_types, contact.full_delassus), so all such variants share their
/// references; else the variant's name.
std::string referenceGroup(const BenchmarkVariant& variant);

/// All cases of a scene's sweep, in a stable order. Models that only support linear tets
/// (mass_spring, ems) are skipped for tet10.
std::vector<CaseSpec> expandSweep(const BenchmarkScene& scene);

/// The runtime scene of one case (what TissueSimulation runs for it): the shared keys of
/// `scene` with the case's resolution, element type, model, integrator and solver.
RuntimeScene caseScene(const BenchmarkScene& scene, const CaseSpec& spec);

/// Runs one case headless and measures it against the scene's reference. A self_reference scene
/// compares with `reference_x`, the selfReferencePositions() of a case with the same
/// selfReferenceKey(), or computes them when it is nullptr; an empty reference_x (the reference
/// run failed) gives error_rel NaN.
/// @throws std::invalid_argument when the scene and case do not fit (e.g. an empty BC region),
///         or reference_x does not have the case's size.
CaseResult runTissueCase(const BenchmarkScene& scene, const CaseSpec& spec,
                         const Eigen::VectorXd* reference_x = nullptr);

/// Final positions [m] of the self_reference run of `spec`: the same mesh, model and loading,
/// Newton implicit Euler (quasi_static for a quasi-static case) with measure.reference_solver and
/// the tolerances of tightReferenceScene().
Eigen::VectorXd selfReferencePositions(const BenchmarkScene& scene, const CaseSpec& spec);

/// Cases with equal keys share their selfReferencePositions(): mesh, model and whether the
/// loading is quasi-static.
std::string selfReferenceKey(const BenchmarkScene& scene, const CaseSpec& spec);

/// Label of a case in reports: "<scene name>_<element type>_<resolution x>x<y>x<z>" for a
/// generated mesh, "<scene name>_<element type>_<file stem>" for a mesh file.
std::string caseLabel(const BenchmarkScene& scene, const CaseSpec& spec);

/// Status of a case in reports: "unsettled" when its steps were ok but it did not settle against
/// a static reference (its error then measures the motion, not the accuracy), else the name of
/// CaseResult::status.
std::string caseStatus(const CaseResult& result);

/// CSV header of tissue_bench rows: case,variant,model,integrator,solver,nodes,elements,dofs,dt,
/// ms_per_step,steps,ms_p99,first_step_ms,ms_after_first,forces_ms,assembly_ms,factor_ms,
/// solve_ms,other_ms,linear_iterations,peak_rss_mb,forces_gflops,forces_gbs,assembly_gflops,
/// assembly_gbs,factor_gflops,factor_gbs,solve_gflops,solve_gbs,error_rel,settled,status (phase
/// times are means per step; other_ms = ms_per_step - the four phases).
const char* caseCsvHeader();
/// One CSV row (no newline) for `result`, labelled `label` (caseLabel()), of the variant named
/// `variant` ("" for a file without variants).
std::string caseCsvRow(const std::string& label, const CaseResult& result,
                       const std::string& variant = "");

}  // namespace surgical_sim::bench
