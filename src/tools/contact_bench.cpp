// contact_bench: tool-in-contact cost of the tissue simulator. For every case of the
// scene's sweep it presses the scene's first tool 6 mm into the top of the body over the first
// two thirds of `steps` (at the body's highest point), holds for the rest, and reports per case: ms
// per step while in contact (mean, p99) split into collision / integrate / contact, the
// integration split into its phases (StepPhaseTimes) and the contact phase into compliance
// solves, LCP and linearization (ContactTimings), the first step's time, the linear iterations,
// the tool-pose-to-contact-model latency (setToolPose() until the new linearization is available;
// mean, p99), the peak resident memory and the final tool force, with its error against the same
// press on the same mesh solved tightly (Newton implicit Euler with measure.reference_solver,
// tolerance 1e-10; one reference run per mesh). Each case and each reference runs in its own
// child process, so peak_rss_mb is that case's own peak (plus the loaded scene's few MB).
// Usage: contact_bench <scene.yaml> [--csv FILE] [--plot FILE]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "surgical_sim/bench/machine_probe.h"
#include "surgical_sim/bench/tissue_case.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace {

using namespace surgical_sim::bench;

constexpr double kDepth = 6e-3;               // indentation of the tip below the rest surface [m]
constexpr double kPressFraction = 2.0 / 3.0;  // share of the steps spent pressing [-]

constexpr const char* kUsage =
    "usage: contact_bench <scene.yaml> [--csv FILE] [--plot FILE]\n"
    "Tool-in-contact cost of every case of the scene's sweep: ms per step (collision, integrate\n"
    "and its phases, contact: compliance solves, LCP, linearization), linear iterations,\n"
    "pose-to-contact-model latency, peak resident memory (each case in its own process) and the\n"
    "tool force against a tight solve of the same mesh (Newton implicit Euler,\n"
    "measure.reference_solver, default cholmod, tolerance 1e-10).\n"
    "  --csv FILE   one row per case\n"
    "  --plot FILE  error against run time (PNG; needs --csv)\n";

int usage(const std::string& msg) {
  std::cerr << "contact_bench: " << msg << "\n" << kUsage;
  return 2;
}

/// One case; times are means over the steps in contact [ms].
struct Row {
  CaseSpec spec;
  int nodes = 0, dofs = 0, contacts = 0, contact_steps = 0;
  double ms_mean = 0, ms_p99 = 0, first_step_ms = 0, collision_ms = 0, integrate_ms = 0,
         contact_ms = 0;
  double forces_ms = 0, assembly_ms = 0, factor_ms = 0, solve_ms = 0, linear_iterations = 0;
  double compliance_ms = 0, compliance_solves = 0, lcp_ms = 0, linearization_ms = 0;
  double latency_mean_ms = 0, latency_p99_ms = 0, peak_rss_mb = 0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  StepStatus status = StepStatus::Ok;
};

double mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (const double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

/// Presses the scene's first tool into the top of the body (see the file comment) and calls
/// onStep(stats, linearization, latency [ms]) after every step.
template <typename OnStep>
void press(const BenchmarkScene& scene, TissueSimulation& sim, OnStep&& onStep) {
  // The body's highest rest point (the organ blob's apex, over its centre) in the tissue frame.
  const double top = sim.mesh().nodes.row(2).maxCoeff();
  const double radius = scene.tools.front().radius;
  Eigen::Isometry3d X_ST = Eigen::Isometry3d::Identity();
  X_ST.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const int press_steps = std::max(1, static_cast<int>(kPressFraction * scene.steps));
  for (int s = 1; s <= scene.steps; ++s) {
    const double depth = kDepth * std::min(1.0, static_cast<double>(s) / press_steps);
    X_ST.translation() = Eigen::Vector3d(0.0, 0.0, top + radius - depth);
    const auto start = std::chrono::steady_clock::now();
    sim.setToolPose(0, X_ST);
    const SimulationStepStats stats = sim.step();
    const ContactLinearization lin = sim.toolContact(0);
    onStep(stats, lin,
           std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
               .count());
  }
}

/// The final tool force of the press on the case's mesh with Newton implicit Euler and
/// measure.reference_solver at tolerance 1e-10 (tightReferenceScene()) [N].
Eigen::Vector3d referenceForce(const BenchmarkScene& scene, CaseSpec spec) {
  spec.integrator = IntegratorKind::ImplicitEulerNewton;
  spec.solver = scene.measure.reference_solver;
  const BenchmarkScene tight = tightReferenceScene(scene);
  TissueSimulation sim(caseScene(tight, spec));
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  press(tight, sim, [&](const SimulationStepStats&, const ContactLinearization& lin, double) {
    force = lin.f0_S;
  });
  return force;
}

Row runCase(const BenchmarkScene& scene, const CaseSpec& spec) {
  TissueSimulation sim(caseScene(scene, spec));
  Row row;
  row.spec = spec;
  row.nodes = sim.model().numNodes();  // DOF nodes (efg: particles)
  row.dofs = 3 * row.nodes;
  std::vector<double> step_ms, latency_ms;
  // Sums over the steps in contact, divided by their number below.
  Row sum;
  bool first = true;
  press(scene, sim,
        [&](const SimulationStepStats& stats, const ContactLinearization& lin, double latency) {
          if (stats.report.status != StepStatus::Ok && row.status == StepStatus::Ok) {
            row.status = stats.report.status;
          }
          if (first) row.first_step_ms = 1e3 * stats.step_seconds;
          first = false;
          if (stats.contacts == 0) return;
          step_ms.push_back(1e3 * stats.step_seconds);
          latency_ms.push_back(latency);
          const StepPhaseTimes& phases = stats.report.phases;
          const ContactTimings& contact = stats.contact_timings;
          sum.collision_ms += 1e3 * stats.collision_seconds;
          sum.integrate_ms += 1e3 * stats.integrate_seconds;
          sum.contact_ms += 1e3 * stats.contact_seconds;
          sum.forces_ms += 1e3 * phases.forces;
          sum.assembly_ms += 1e3 * phases.assembly;
          sum.factor_ms += 1e3 * phases.factorization;
          sum.solve_ms += 1e3 * phases.linear_solve;
          sum.linear_iterations += stats.report.linear_iterations;
          sum.compliance_ms += contact.compliance_ms;
          sum.compliance_solves += static_cast<double>(contact.compliance_solves);
          sum.lcp_ms += contact.lcp_ms;
          sum.linearization_ms += contact.linearization_ms;
          row.contacts = std::max(row.contacts, stats.contacts);
          row.force = lin.f0_S;
        });
  row.peak_rss_mb = peakResidentBytes() / 1e6;
  row.contact_steps = static_cast<int>(step_ms.size());
  const double n = std::max<double>(1.0, row.contact_steps);
  row.ms_mean = mean(step_ms);
  row.ms_p99 = percentile99(step_ms);
  for (auto field :
       {&Row::collision_ms, &Row::integrate_ms, &Row::contact_ms, &Row::forces_ms,
        &Row::assembly_ms, &Row::factor_ms, &Row::solve_ms, &Row::linear_iterations,
        &Row::compliance_ms, &Row::compliance_solves, &Row::lcp_ms, &Row::linearization_ms})
    row.*field = sum.*field / n;
  row.latency_mean_ms = mean(latency_ms);
  row.latency_p99_ms = percentile99(latency_ms);
  return row;
}

std::string csvRow(const std::string& scene_name, const std::string& variant, const Row& r) {
  std::ostringstream os;
  os << scene_name << "_" << r.spec.resolution.x() << "," << variant << ","
     << modelName(r.spec.model) << "," << integratorName(r.spec.integrator) << ","
     << solverName(r.spec.solver) << "," << r.nodes << "," << r.dofs << "," << r.contact_steps
     << "," << r.contacts << "," << r.ms_mean << "," << r.ms_p99 << "," << r.first_step_ms << ","
     << r.collision_ms << "," << r.integrate_ms << "," << r.contact_ms << "," << r.forces_ms << ","
     << r.assembly_ms << "," << r.factor_ms << "," << r.solve_ms << "," << r.linear_iterations
     << "," << r.compliance_ms << "," << r.compliance_solves << "," << r.lcp_ms << ","
     << r.linearization_ms << "," << r.latency_mean_ms << "," << r.latency_p99_ms << ","
     << r.peak_rss_mb << "," << r.force.x() << "," << r.force.y() << "," << r.force.z() << ","
     << toString(r.status);
  return os.str();
}

/// A force [N] as three numbers at full precision, and back (NaN components if unreadable).
std::string forceText(const Eigen::Vector3d& f) {
  std::ostringstream os;
  os.precision(17);
  os << f.x() << " " << f.y() << " " << f.z();
  return os.str();
}

Eigen::Vector3d parseForce(const std::string& text) {
  Eigen::Vector3d f = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  std::istringstream is(text);
  for (int k = 0; k < 3; ++k) {
    std::string word;
    if (!(is >> word)) break;
    f[k] = std::strtod(word.c_str(), nullptr);  // reads "nan" and "inf" too
  }
  return f;
}

constexpr const char* kHeader =
    "case,variant,model,integrator,solver,nodes,dofs,contact_steps,max_contacts,ms_per_step,ms_p99,"
    "first_step_ms,collision_ms,integrate_ms,contact_ms,forces_ms,assembly_ms,factor_ms,solve_ms,"
    "linear_iterations,compliance_ms,compliance_solves,lcp_ms,linearization_ms,latency_mean_ms,"
    "latency_p99_ms,peak_rss_mb,force_x,force_y,force_z,status,error_rel";

}  // namespace

int main(int argc, char** argv) {
  namespace tools = surgical_sim::tools;
  if (tools::wantsHelp(argc, argv)) {
    std::cout << kUsage;
    return 0;
  }
  tools::SceneBenchArgs args;
  const std::string error = tools::parseSceneBenchArgs(argc, argv, args);
  if (!error.empty()) return usage(error);

  std::vector<BenchmarkVariant> variants;
  try {
    const BenchmarkScene file = loadBenchmarkScene(args.scene);
    variants = benchVariants(file);
    for (const BenchmarkVariant& v : variants)
      if (v.scene.tools.empty()) return usage("scene " + args.scene + " has no tools");
  } catch (const std::exception& e) {
    std::cerr << "contact_bench: " << e.what() << "\n";
    return 1;
  }
  std::ofstream csv;
  if (!tools::openCsv("contact_bench", args.csv, csv)) return 1;
  std::cout << kHeader << std::endl;
  if (csv) csv << kHeader << "\n";
  // Reference per reference group and mesh: the same press solved tightly (NaN if it failed).
  std::map<std::string, Eigen::Vector3d> references;
  int failures = 0;
  for (const BenchmarkVariant& variant : variants) {
    const BenchmarkScene& scene = variant.scene;
    const std::vector<CaseSpec> cases = expandSweep(scene);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const CaseSpec& spec = cases[i];
      const std::string what = (variant.name.empty() ? "" : variant.name + ": ") +
                               std::to_string(spec.resolution.x()) + " cells, " +
                               solverName(spec.solver);
      tools::progress("contact_bench", tools::caseCounter(i, cases.size()) + what);
      const std::string mesh = referenceGroup(variant) + "/" + caseLabel(scene, spec);
      if (references.count(mesh) == 0) {
        tools::progress("contact_bench", "reference for " + mesh);
        const std::optional<std::string> text =
            tools::runCaseInChild("contact_bench", "reference for " + mesh, [&] {
              applyBenchThreads(scene);
              return forceText(referenceForce(scene, spec));
            });
        references[mesh] =
            text ? parseForce(*text)
                 : Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
      }
      // The child sends the force, a line break and the row without its error column.
      const std::optional<std::string> text =
          tools::runCaseInChild("contact_bench", "case " + what, [&] {
            applyBenchThreads(scene);
            const Row r = runCase(scene, spec);
            return forceText(r.force) + "\n" + csvRow(scene.name, variant.name, r);
          });
      if (!text) {
        ++failures;
        continue;
      }
      const std::size_t line_end = text->find('\n');
      const Eigen::Vector3d force = parseForce(text->substr(0, line_end));
      const Eigen::Vector3d& f_ref = references[mesh];
      double error_rel = std::numeric_limits<double>::quiet_NaN();
      if (f_ref.allFinite() && f_ref.norm() > 0.0 && force.allFinite())
        error_rel = (force - f_ref).norm() / f_ref.norm();
      std::ostringstream row;
      row << text->substr(line_end + 1) << "," << error_rel;
      std::cout << row.str() << std::endl;
      if (csv) csv << row.str() << "\n" << std::flush;
    }
  }
  if (!args.plot.empty()) {
    csv.close();
    if (!tools::runPlotScript(
            "contact_bench", "plot_error_vs_time.py",
            {args.csv, args.plot,
             variants.front().scene.name + " (force vs tight Newton, same mesh)"})) {
      return 1;
    }
  }
  return failures == 0 ? 0 : 1;
}
