#include "surgical_sim/bench/tissue_case.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "surgical_sim/bench/machine_probe.h"
#include "surgical_sim/bench/phase_work.h"
#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/gmsh_reader.h"
#include "surgical_sim/core/mesh/mesh_check.h"
#include "surgical_sim/core/scene/scene_build.h"
#include "surgical_sim/core/tissue/efg_model.h"

namespace surgical_sim::bench {
namespace {

/// Cross-section area [m^2], second moment about the bending axis [m^4] and the Cowper shear
/// coefficient of the scene's beam, for the analytic references.
struct BeamSection {
  double area = 0.0;
  double inertia = 0.0;
  double shear_coefficient = 0.0;
  double length = 0.0;
};

BeamSection beamSection(const BenchmarkScene& scene, int bending_component) {
  const MeshSpec& m = scene.mesh;
  const double nu = scene.material.poisson_ratio;
  BeamSection s;
  if (m.generator == "hex_beam") {
    const double a = m.hex_side;
    s.area = 1.5 * std::sqrt(3.0) * a * a;
    s.inertia = 5.0 * std::sqrt(3.0) / 16.0 * a * a * a * a;
    s.shear_coefficient = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu);  // solid, near-circular section
    s.length = m.hex_length;
  } else if (m.generator == "beam" || m.generator == "box") {
    const double b = m.size[bending_component == 1 ? 2 : 1];  // width across the bending plane
    const double h = m.size[bending_component];               // depth in the bending plane
    s.area = b * h;
    s.inertia = b * h * h * h / 12.0;
    s.shear_coefficient = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);  // rectangle
    s.length = m.size[0];
  } else {
    throw std::invalid_argument("scene " + scene.path +
                                ": key 'measure.reference_formula' needs a beam, box or hex_beam "
                                "mesh generator");
  }
  return s;
}

double analyticTipReference(const BenchmarkScene& scene) {
  const MeasureSpec& m = scene.measure;
  if (m.reference) return *m.reference;
  const Material& mat = scene.material;
  const double g = scene.gravity[m.component];
  const BeamSection s = beamSection(scene, m.component);
  if (m.reference_formula == "axial_self_weight")
    return mat.density * g * s.length * s.length / (2.0 * mat.young_modulus);
  // Euler-Bernoulli q L^4 / (8 E I) plus Timoshenko shear q L^2 / (2 kappa G A).
  const double q = mat.density * g * s.area;  // signed line load [N/m]
  const double L = s.length;
  return q * L * L * L * L / (8.0 * mat.young_modulus * s.inertia) +
         q * L * L / (2.0 * s.shear_coefficient * mat.mu() * s.area);
}

/// The efg settings of one case: the scene's, with the spacing of the case's resolution when
/// efg.spacing lists one per resolution.
EfgOptions caseEfgOptions(const BenchmarkScene& scene, const CaseSpec& spec) {
  EfgOptions efg = scene.efg;
  if (scene.efg_spacings.size() > 1) {
    const auto it = std::find(scene.resolutions.begin(), scene.resolutions.end(), spec.resolution);
    if (it != scene.resolutions.end())
      efg.spacing = scene.efg_spacings[static_cast<std::size_t>(it - scene.resolutions.begin())];
  }
  return efg;
}

/// Mean displacement component `component` [m] of the mesh nodes in `region` at model positions
/// x (rest x0): the nodes' own DOFs for tet models, the model's interpolation at the nodes for
/// efg. Empty region: NaN.
double meanRegionDisplacement(const TetMesh& mesh, const TissueModel& model, const Region& region,
                              int component, const Eigen::VectorXd& x, const Eigen::VectorXd& x0) {
  const Eigen::Map<const Eigen::VectorXd> nodes(mesh.nodes.data(), mesh.nodes.size());
  const std::vector<int> dofs = regionDofs(nodes, region, Eigen::Vector3i::Unit(component));
  if (dofs.empty()) return std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd u(static_cast<Eigen::Index>(dofs.size()));
  if (const auto* efg = dynamic_cast<const EfgModel*>(&model)) {
    Eigen::Matrix3Xd points(3, u.size());
    for (Eigen::Index i = 0; i < u.size(); ++i)
      points.col(i) = nodes.segment<3>(3 * (dofs[static_cast<std::size_t>(i)] / 3));
    const Eigen::SparseMatrix<double> W = efg->interpolation(points);
    const Eigen::VectorXd du = x - x0;
    u = W * Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<3>>(du.data() + component,
                                                                        du.size() / 3);
  } else {
    for (Eigen::Index i = 0; i < u.size(); ++i) {
      const int d = dofs[static_cast<std::size_t>(i)];
      u(i) = x[d] - x0[d];
    }
  }
  return u.mean();
}

/// Prescribed part of the Dirichlet set, with rest positions and unit-load displacements.
struct PrescribedDofs {
  std::vector<int> dofs;
  std::vector<double> rest;
  std::vector<double> unit_displacement;
};

struct CaseSetup {
  TetMesh mesh;
  std::unique_ptr<TissueModel> model;
  DynamicsProblem problem;
  std::size_t fixed_dofs =
      0;  ///< the first fixed_dofs Dirichlet DOFs are fixed, the rest prescribed
  PrescribedDofs prescribed;
};

CaseSetup setUp(const BenchmarkScene& scene, const CaseSpec& spec) {
  CaseSetup c;
  c.mesh = buildSceneMesh(scene.mesh, spec.resolution, spec.element_type);
  requireValidMesh(c.mesh);
  c.model = makeTissueModel(spec.model, c.mesh, scene.material, caseEfgOptions(scene, spec));
  c.problem.model = c.model.get();
  c.problem.external_force = c.model->bodyForce(scene.gravity);
  c.problem.damping.mass_coefficient = scene.damping_mass;
  c.problem.damping.stiffness_coefficient = scene.damping_stiffness;
  const Eigen::VectorXd& rest = c.model->restPositions();
  c.problem.dirichlet = fixedDirichlet(scene, rest);
  c.fixed_dofs = c.problem.dirichlet.dofs.size();
  std::vector<bool> taken(static_cast<std::size_t>(rest.size()), false);
  for (const int d : c.problem.dirichlet.dofs) taken[static_cast<std::size_t>(d)] = true;
  for (std::size_t i = 0; i < scene.prescribed.size(); ++i) {
    const PrescribedBc& bc = scene.prescribed[i];
    const std::size_t first = c.prescribed.dofs.size();
    appendRegionDofs(rest, bc.region, bc.components, "prescribed[" + std::to_string(i) + "]",
                     scene.path, taken, c.prescribed.dofs);
    for (std::size_t k = first; k < c.prescribed.dofs.size(); ++k) {
      const int d = c.prescribed.dofs[k];
      c.prescribed.rest.push_back(rest[d]);
      c.prescribed.unit_displacement.push_back(bc.displacement[d % 3]);
    }
  }
  DirichletBc& bc = c.problem.dirichlet;
  bc.dofs.insert(bc.dofs.end(), c.prescribed.dofs.begin(), c.prescribed.dofs.end());
  bc.positions.conservativeResize(static_cast<Eigen::Index>(bc.dofs.size()));
  for (std::size_t i = c.fixed_dofs; i < bc.dofs.size(); ++i)
    bc.positions[static_cast<Eigen::Index>(i)] = rest[bc.dofs[i]];
  return c;
}

/// Sets the prescribed DOFs' targets to rest + factor * displacement.
void applyLoadFactor(CaseSetup& c, double factor) {
  const auto offset = static_cast<Eigen::Index>(c.fixed_dofs);
  for (std::size_t i = 0; i < c.prescribed.dofs.size(); ++i)
    c.problem.dirichlet.positions[offset + static_cast<Eigen::Index>(i)] =
        c.prescribed.rest[i] + factor * c.prescribed.unit_displacement[i];
}

/// Runs the load / time stepping of one case; returns positions; fills timing and status.
struct RunOutcome {
  Eigen::VectorXd x;
  double seconds = 0.0;
  int steps = 0;
  std::vector<double> step_ms;  ///< wall time of every step [ms]
  StepPhaseTimes phases;        ///< summed over the steps [s]
  long linear_iterations = 0;   ///< summed over the steps
  StepStatus status = StepStatus::Ok;
  std::vector<double> step_changes;  ///< |x_k - x_(k-1)|_inf of every step k [m]
  std::vector<double> path_values;   ///< uniaxial: measured force at each load factor
  std::vector<double> path_factors;
};

void recordStatus(RunOutcome& out, StepStatus s) {
  if (out.status == StepStatus::Ok) out.status = s;
}

double reactionForce(const CaseSetup& c, int component, const Eigen::VectorXd& x,
                     Eigen::VectorXd& work) {
  work.setZero();
  c.model->addInternalForce(x, work);
  double sum = 0.0;
  for (int d : c.prescribed.dofs)
    if (d % 3 == component) sum -= work[d];
  return sum;
}

RunOutcome runLoading(const BenchmarkScene& scene, CaseSetup& c, Integrator& integrator) {
  RunOutcome out;
  SimulationState state;
  state.x = c.model->restPositions();
  state.v = Eigen::VectorXd::Zero(state.x.size());
  const Eigen::VectorXd full_load = c.problem.external_force;
  const bool quasi_static = integrator.name() == "quasi_static";

  Eigen::VectorXd previous_x;
  const auto timedStep = [&](double dt) {
    previous_x = state.x;
    Stopwatch watch;
    const StepReport r = integrator.step(c.problem, dt, state);
    const double seconds = watch.seconds();
    out.seconds += seconds;
    out.step_ms.push_back(1e3 * seconds);
    out.phases.forces += r.phases.forces;
    out.phases.assembly += r.phases.assembly;
    out.phases.factorization += r.phases.factorization;
    out.phases.linear_solve += r.phases.linear_solve;
    out.linear_iterations += r.linear_iterations;
    ++out.steps;
    out.step_changes.push_back((state.x - previous_x).lpNorm<Eigen::Infinity>());
    if (r.status != StepStatus::Ok) recordStatus(out, r.status);
    return r.status;
  };

  if (scene.measure.type == "uniaxial_svk_force") {
    // Continuation from the rest state outwards: compression branch, then tension branch.
    std::vector<double> neg, pos;
    for (double f : scene.load_factors) (f < 0 ? neg : pos).push_back(f);
    std::sort(neg.begin(), neg.end(), std::greater<double>());
    std::sort(pos.begin(), pos.end());
    Eigen::VectorXd work(state.x.size());
    for (const auto* branch : {&neg, &pos}) {
      state.x = c.model->restPositions();
      state.v.setZero();
      double previous = 0.0;
      for (double target : *branch) {
        for (int k = 1; k <= scene.steps; ++k) {
          applyLoadFactor(c, previous + (target - previous) * k / scene.steps);
          if (timedStep(scene.time_step) == StepStatus::SolverFailed) break;
        }
        previous = target;
        out.path_factors.push_back(target);
        out.path_values.push_back(reactionForce(c, scene.measure.component, state.x, work));
      }
    }
  } else {
    for (int k = 1; k <= scene.steps; ++k) {
      if (quasi_static) c.problem.external_force = full_load * (double(k) / scene.steps);
      const StepStatus s = timedStep(scene.time_step);
      if (s == StepStatus::SolverFailed || s == StepStatus::NonFinite || s == StepStatus::BlowUp)
        break;
    }
    c.problem.external_force = full_load;
  }
  out.x = state.x;
  return out;
}

/// CaseResult::settled of `run` (rest positions x0).
bool settledAtEnd(const RunOutcome& run, const Eigen::VectorXd& x0, bool quasi_static) {
  if (quasi_static) return true;
  const std::size_t n = run.step_changes.size();
  const std::size_t window = std::max<std::size_t>(2, n / 10);
  if (n < window || !run.x.allFinite()) return false;
  const double bound = kSettledStepChange * (run.x - x0).lpNorm<Eigen::Infinity>();
  return std::all_of(run.step_changes.end() - static_cast<std::ptrdiff_t>(window),
                     run.step_changes.end(), [&](double change) { return change <= bound; });
}

/// Throughput of a linearized implicit Euler run of case `c` (see CaseResult::rates).
PhaseRates phaseRates(const CaseSetup& c, const CaseSpec& spec, const RunOutcome& run) {
  PhaseRates r;
  if (spec.integrator != IntegratorKind::ImplicitEulerLinearized || run.steps == 0) return r;
  const Eigen::SparseMatrix<double>& pattern = c.model->stiffnessPattern();
  WorkShape shape;
  shape.model = spec.model;
  shape.element_type = spec.element_type;
  shape.solver = spec.solver;
  shape.elements = c.mesh.numElements();
  shape.dofs = static_cast<double>(pattern.rows());
  shape.matrix_nonzeros = static_cast<double>(pattern.nonZeros());
  if (spec.solver == SolverKind::Cholmod || spec.solver == SolverKind::PcgCholeskyReuse ||
      spec.solver == SolverKind::PcgCholeskyBackground ||
      spec.solver == SolverKind::PcgCholeskyWarped)
    std::tie(shape.factor_nonzeros, shape.factor_flops) = choleskyFactorSize(pattern);
  const StepWork work = estimateStepWork(shape);
  const auto rate = [](double amount, double count, double seconds) {
    return seconds > 0.0 ? amount * count / seconds / 1e9 : kNoRate;
  };
  const double steps = run.steps;
  const auto iterations = static_cast<double>(run.linear_iterations);
  r.forces_gflops = rate(work.forces.flops, steps, run.phases.forces);
  r.forces_gbs = rate(work.forces.bytes, steps, run.phases.forces);
  r.assembly_gflops = rate(work.assembly.flops, steps, run.phases.assembly);
  r.assembly_gbs = rate(work.assembly.bytes, steps, run.phases.assembly);
  r.factorization_gflops = rate(work.factorization.flops, steps, run.phases.factorization);
  r.factorization_gbs = rate(work.factorization.bytes, steps, run.phases.factorization);
  r.solve_gflops = rate(work.solve_iteration.flops, iterations, run.phases.linear_solve);
  r.solve_gbs = rate(work.solve_iteration.bytes, iterations, run.phases.linear_solve);
  return r;
}

}  // namespace

double percentile99(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto k = static_cast<size_t>(std::ceil(0.99 * static_cast<double>(values.size()))) - 1;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

BenchmarkScene tightReferenceScene(const BenchmarkScene& scene) {
  BenchmarkScene tight = scene;
  tight.newton_tolerance = kReferenceTolerance;
  tight.newton_max_iterations = kReferenceNewtonIterations;
  tight.pcg_tolerance = kReferenceTolerance;
  tight.pcg_max_iterations.reset();
  return tight;
}

std::vector<BenchmarkVariant> benchVariants(const BenchmarkScene& scene) {
  if (!scene.variants.empty()) return scene.variants;
  return {{"", scene, {}}};
}

void applyBenchThreads(const BenchmarkScene& scene) {
  if (scene.threads) setenv("SURGICAL_SIM_THREADS", std::to_string(*scene.threads).c_str(), 1);
}

std::string referenceGroup(const BenchmarkVariant& variant) {
  const auto solver_only = [](const std::string& key) {
    for (const char* k : {"solvers", "integrators", "models", "threads", "mesh.resolutions",
                          "mesh.element_types", "contact.full_delassus"})
      if (key == k) return true;
    return key.rfind("pcg.", 0) == 0 || key.rfind("newton.", 0) == 0;
  };
  return std::all_of(variant.keys.begin(), variant.keys.end(), solver_only) ? "" : variant.name;
}

std::vector<CaseSpec> expandSweep(const BenchmarkScene& scene) {
  std::vector<CaseSpec> cases;
  for (ElementType type : scene.element_types)
    for (const auto& res : scene.resolutions)
      for (const auto& model : scene.models) {
        if (type != ElementType::Tet4 && linearTetOnly(model)) continue;
        // efg uses the mesh only for its volume: one element type is enough.
        if (model == ModelKind::Efg && type != scene.element_types.front()) continue;
        for (const auto& integrator : scene.integrators)
          for (const auto& solver : scene.solvers)
            cases.push_back({res, type, model, integrator, solver});
      }
  return cases;
}

RuntimeScene caseScene(const BenchmarkScene& scene, const CaseSpec& spec) {
  RuntimeScene one;
  static_cast<SceneBase&>(one) = scene;
  one.resolution = spec.resolution;
  one.element_type = spec.element_type;
  one.model = spec.model;
  one.integrator = spec.integrator;
  one.solver = spec.solver;
  one.efg = caseEfgOptions(scene, spec);
  if (!scene.efg_spacings.empty()) one.efg_spacings = {one.efg.spacing};
  return one;
}

Eigen::VectorXd selfReferencePositions(const BenchmarkScene& scene, const CaseSpec& spec) {
  CaseSetup ref_setup = setUp(scene, spec);
  const IntegratorKind ref_integrator = spec.integrator == IntegratorKind::QuasiStatic
                                            ? IntegratorKind::QuasiStatic
                                            : IntegratorKind::ImplicitEulerNewton;
  const BenchmarkScene ref_scene = tightReferenceScene(scene);
  auto ref = makeSceneIntegrator(ref_scene, ref_integrator, scene.measure.reference_solver,
                                 ref_scene.newton_tolerance);
  return runLoading(ref_scene, ref_setup, *ref).x;
}

std::string selfReferenceKey(const BenchmarkScene& scene, const CaseSpec& spec) {
  return caseLabel(scene, spec) + "/" + modelName(spec.model) +
         (spec.integrator == IntegratorKind::QuasiStatic ? "/quasi_static" : "/dynamic");
}

CaseResult runTissueCase(const BenchmarkScene& scene, const CaseSpec& spec,
                         const Eigen::VectorXd* reference_x) {
  CaseSetup c = setUp(scene, spec);
  CaseResult result;
  result.spec = spec;
  const auto* efg = dynamic_cast<const EfgModel*>(c.model.get());
  result.nodes = c.model->numNodes();
  result.elements =
      efg != nullptr ? static_cast<int>(efg->grid().volumes.size()) : c.mesh.numElements();
  result.dofs = 3 * result.nodes;
  result.dt = scene.time_step;

  auto integrator =
      makeSceneIntegrator(scene, spec.integrator, spec.solver, scene.newton_tolerance);
  const RunOutcome run = runLoading(scene, c, *integrator);
  result.steps = run.steps;
  result.ms_per_step = run.steps > 0 ? 1e3 * run.seconds / run.steps : 0.0;
  result.ms_p99 = percentile99(run.step_ms);
  result.first_step_ms = run.step_ms.empty() ? 0.0 : run.step_ms.front();
  if (run.steps > 1)
    result.ms_after_first = (1e3 * run.seconds - result.first_step_ms) / (run.steps - 1);
  const double per_step = run.steps > 0 ? 1.0 / run.steps : 0.0;
  result.phases.forces = per_step * run.phases.forces;
  result.phases.assembly = per_step * run.phases.assembly;
  result.phases.factorization = per_step * run.phases.factorization;
  result.phases.linear_solve = per_step * run.phases.linear_solve;
  result.linear_iterations = per_step * static_cast<double>(run.linear_iterations);
  result.peak_rss_bytes = peakResidentBytes();
  result.rates = phaseRates(c, spec, run);
  result.status = run.status;

  const MeasureSpec& m = scene.measure;
  const Eigen::VectorXd& x0 = c.model->restPositions();
  result.settled = settledAtEnd(run, x0, spec.integrator == IntegratorKind::QuasiStatic);
  result.static_reference = m.type == "tip_displacement" || m.type == "uniaxial_svk_force";
  if (m.type == "tip_displacement") {
    result.measured = meanRegionDisplacement(c.mesh, *c.model, m.region, m.component, run.x, x0);
    if (std::isnan(result.measured))
      throw std::invalid_argument("scene " + scene.path +
                                  ": key 'measure.region' contains no mesh node");
    result.reference = analyticTipReference(scene);
    result.error_rel = std::abs(result.measured - result.reference) / std::abs(result.reference);
  } else if (m.type == "uniaxial_svk_force") {
    // f(l) = (E S0 / 2) l (l^2 - 1); report the worst relative error over the path (l = 1,
    // where f = 0, is normalised by the peak compressive force E S0 / (3 sqrt 3) instead).
    const double es0 = scene.material.young_modulus * m.face_area;
    const double unit = c.prescribed.unit_displacement.empty()
                            ? 0.0
                            : scene.prescribed.front().displacement[m.component];
    const double f_peak = es0 / (3.0 * std::sqrt(3.0));
    double worst = 0.0;
    for (std::size_t i = 0; i < run.path_factors.size(); ++i) {
      const double l = 1.0 + run.path_factors[i] * unit / m.rest_length;
      const double exact = 0.5 * es0 * l * (l * l - 1.0);
      const double err =
          std::abs(run.path_values[i] - exact) / (exact != 0.0 ? std::abs(exact) : f_peak);
      result.path_stretch.push_back(l);
      result.path_force.push_back(run.path_values[i]);
      result.path_exact.push_back(exact);
      if (err >= worst) {
        worst = err;
        result.measured = run.path_values[i];
        result.reference = exact;
      }
    }
    result.error_rel = worst;
  } else {  // self_reference: same mesh, tight Newton (measure.reference_solver)
    const Eigen::VectorXd ref_x =
        reference_x != nullptr ? *reference_x : selfReferencePositions(scene, spec);
    result.measured = (run.x - x0).norm();
    if (ref_x.size() == 0) {  // no reference run: error_rel NaN (below)
      result.reference = std::numeric_limits<double>::quiet_NaN();
    } else {
      if (ref_x.size() != run.x.size())
        throw std::invalid_argument("runTissueCase: reference positions of size " +
                                    std::to_string(ref_x.size()) + " for a case of " +
                                    std::to_string(run.x.size()) + " DOFs");
      result.reference = (ref_x - x0).norm();
      result.error_rel = (run.x - ref_x).norm() / result.reference;
    }
  }
  // A relative error against a zero or non-finite reference (e.g. a self_reference scene with
  // no load) is meaningless; uniaxial_svk_force normalises by a non-zero force instead.
  const bool relative_to_reference = m.type != "uniaxial_svk_force";
  if (relative_to_reference && !(std::isfinite(result.reference) && result.reference != 0.0))
    result.error_rel = std::numeric_limits<double>::quiet_NaN();
  if (!run.x.allFinite() || result.status == StepStatus::SolverFailed ||
      result.status == StepStatus::NonFinite || result.status == StepStatus::BlowUp)
    result.error_rel = std::numeric_limits<double>::quiet_NaN();
  return result;
}

std::string caseLabel(const BenchmarkScene& scene, const CaseSpec& spec) {
  std::ostringstream label;
  label << scene.name << "_" << toString(spec.element_type) << "_";
  if (scene.mesh.generator == "file")
    label << std::filesystem::path(scene.mesh.file).stem().string();
  else
    label << spec.resolution[0] << "x" << spec.resolution[1] << "x" << spec.resolution[2];
  return label.str();
}

std::string caseStatus(const CaseResult& r) {
  if (r.status == StepStatus::Ok && r.static_reference && !r.settled) return "unsettled";
  return toString(r.status);
}

const char* caseCsvHeader() {
  return "case,variant,model,integrator,solver,nodes,elements,dofs,dt,ms_per_step,steps,ms_p99,"
         "first_step_ms,ms_after_first,forces_ms,assembly_ms,factor_ms,solve_ms,other_ms,"
         "linear_iterations,peak_rss_mb,forces_gflops,forces_gbs,assembly_gflops,assembly_gbs,"
         "factor_gflops,factor_gbs,solve_gflops,solve_gbs,error_rel,settled,status";
}

std::string caseCsvRow(const std::string& label, const CaseResult& r, const std::string& variant) {
  std::ostringstream row;
  row << label << "," << variant << "," << modelName(r.spec.model) << ","
      << integratorName(r.spec.integrator) << "," << solverName(r.spec.solver) << "," << r.nodes
      << "," << r.elements << "," << r.dofs << "," << r.dt << "," << r.ms_per_step << "," << r.steps
      << "," << r.ms_p99 << "," << r.first_step_ms << "," << r.ms_after_first << ","
      << 1e3 * r.phases.forces << "," << 1e3 * r.phases.assembly << ","
      << 1e3 * r.phases.factorization << "," << 1e3 * r.phases.linear_solve << ","
      << r.ms_per_step - 1e3 * r.phases.sum() << "," << r.linear_iterations << ","
      << r.peak_rss_bytes / 1e6 << "," << r.rates.forces_gflops << "," << r.rates.forces_gbs << ","
      << r.rates.assembly_gflops << "," << r.rates.assembly_gbs << ","
      << r.rates.factorization_gflops << "," << r.rates.factorization_gbs << ","
      << r.rates.solve_gflops << "," << r.rates.solve_gbs << "," << r.error_rel << ","
      << (r.settled ? 1 : 0) << "," << caseStatus(r);
  return row.str();
}

}  // namespace surgical_sim::bench
