// contact_bench: tool-in-contact cost of the tissue simulator. For every case of the
// scene's sweep it presses the scene's first tool 6 mm into the top of the body over the first
// two thirds of `steps` (at the body's highest point), holds for the rest, and reports per case: ms
// per step while in contact (mean, p99) split into collision / integrate / contact, the
// tool-pose-to-contact-model latency (setToolPose() until the new linearization is available; mean,
// p99) and the final tool force, with its error against the same press on the same mesh solved
// tightly (Newton implicit Euler, CHOLMOD, tolerance 1e-10; one reference run per mesh).
// Usage: contact_bench <scene.yaml> [--csv FILE] [--plot FILE]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "surgical_sim/bench/tissue_case.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace {

using namespace surgical_sim::bench;

constexpr double kDepth = 6e-3;               // indentation of the tip below the rest surface [m]
constexpr double kPressFraction = 2.0 / 3.0;  // share of the steps spent pressing [-]

constexpr const char* kUsage =
    "usage: contact_bench <scene.yaml> [--csv FILE] [--plot FILE]\n"
    "Tool-in-contact cost of every case of the scene's sweep: ms per step (collision, integrate,\n"
    "contact), pose-to-contact-model latency and the tool force against a tight solve of the\n"
    "same mesh (Newton implicit Euler, CHOLMOD, tolerance 1e-10).\n"
    "  --csv FILE   one row per case\n"
    "  --plot FILE  error against run time (PNG; needs --csv)\n";

int usage(const std::string& msg) {
  std::cerr << "contact_bench: " << msg << "\n" << kUsage;
  return 2;
}

struct Row {
  CaseSpec spec;
  int nodes = 0, dofs = 0, contacts = 0, contact_steps = 0;
  double ms_mean = 0, ms_p99 = 0, collision_ms = 0, integrate_ms = 0, contact_ms = 0;
  double latency_mean_ms = 0, latency_p99_ms = 0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  double error_rel = std::numeric_limits<double>::quiet_NaN();
  StepStatus status = StepStatus::Ok;
};

double mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (const double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

double p99(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<size_t>(std::ceil(0.99 * static_cast<double>(v.size()))) - 1;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
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

/// The final tool force of the press on the case's mesh with Newton implicit Euler and CHOLMOD
/// at tolerance 1e-10 [N].
Eigen::Vector3d referenceForce(BenchmarkScene scene, CaseSpec spec) {
  spec.integrator = IntegratorKind::ImplicitEulerNewton;
  spec.solver = SolverKind::Cholmod;
  scene.newton_tolerance = 1e-10;
  scene.newton_max_iterations = 50;
  TissueSimulation sim(caseScene(scene, spec));
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  press(scene, sim, [&](const SimulationStepStats&, const ContactLinearization& lin, double) {
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
  double collision = 0, integrate = 0, contact = 0;
  press(scene, sim,
        [&](const SimulationStepStats& stats, const ContactLinearization& lin, double latency) {
          if (stats.report.status != StepStatus::Ok && row.status == StepStatus::Ok) {
            row.status = stats.report.status;
          }
          if (stats.contacts == 0) return;
          step_ms.push_back(1e3 * stats.step_seconds);
          latency_ms.push_back(latency);
          collision += 1e3 * stats.collision_seconds;
          integrate += 1e3 * stats.integrate_seconds;
          contact += 1e3 * stats.contact_seconds;
          row.contacts = std::max(row.contacts, stats.contacts);
          row.force = lin.f0_S;
        });
  row.contact_steps = static_cast<int>(step_ms.size());
  const double n = std::max<double>(1.0, row.contact_steps);
  row.ms_mean = mean(step_ms);
  row.ms_p99 = p99(step_ms);
  row.collision_ms = collision / n;
  row.integrate_ms = integrate / n;
  row.contact_ms = contact / n;
  row.latency_mean_ms = mean(latency_ms);
  row.latency_p99_ms = p99(latency_ms);
  return row;
}

std::string csvRow(const std::string& scene_name, const Row& r) {
  std::ostringstream os;
  os << scene_name << "_" << r.spec.resolution.x() << "," << modelName(r.spec.model) << ","
     << integratorName(r.spec.integrator) << "," << solverName(r.spec.solver) << "," << r.nodes
     << "," << r.dofs << "," << r.contact_steps << "," << r.contacts << "," << r.ms_mean << ","
     << r.ms_p99 << "," << r.collision_ms << "," << r.integrate_ms << "," << r.contact_ms << ","
     << r.latency_mean_ms << "," << r.latency_p99_ms << "," << r.force.z() << "," << r.error_rel
     << "," << toString(r.status);
  return os.str();
}

constexpr const char* kHeader =
    "case,model,integrator,solver,nodes,dofs,contact_steps,max_contacts,ms_per_step,ms_p99,"
    "collision_ms,integrate_ms,contact_ms,latency_mean_ms,latency_p99_ms,force_z,error_rel,"
    "status";

}  // namespace

int main(int argc, char** argv) {
  if (surgical_sim::tools::wantsHelp(argc, argv)) {
    std::cout << kUsage;
    return 0;
  }
  surgical_sim::tools::SceneBenchArgs args;
  const std::string error = surgical_sim::tools::parseSceneBenchArgs(argc, argv, args);
  if (!error.empty()) return usage(error);

  std::vector<Row> rows;
  BenchmarkScene scene;
  try {
    scene = loadBenchmarkScene(args.scene);
    if (scene.tools.empty()) return usage("scene " + args.scene + " has no tools");
    const std::vector<CaseSpec> cases = expandSweep(scene);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      surgical_sim::tools::progress("contact_bench",
                                    surgical_sim::tools::caseCounter(i, cases.size()) +
                                        std::to_string(cases[i].resolution.x()) + " cells, " +
                                        solverName(cases[i].solver));
      rows.push_back(runCase(scene, cases[i]));
    }
  } catch (const std::exception& e) {
    std::cerr << "contact_bench: " << e.what() << "\n";
    return 1;
  }
  // Reference per mesh: the same press solved tightly on that mesh.
  std::map<std::string, Eigen::Vector3d> references;
  for (Row& r : rows) {
    const std::string mesh = caseLabel(scene, r.spec);
    if (references.count(mesh) == 0) {
      surgical_sim::tools::progress("contact_bench", "reference for " + mesh);
      references[mesh] = referenceForce(scene, r.spec);
    }
    const Eigen::Vector3d& f_ref = references[mesh];
    if (f_ref.allFinite() && f_ref.norm() > 0.0 && r.force.allFinite()) {
      r.error_rel = (r.force - f_ref).norm() / f_ref.norm();
    }
  }
  std::ofstream csv;
  if (!surgical_sim::tools::openCsv("contact_bench", args.csv, csv)) return 1;
  std::cout << kHeader << "\n";
  if (csv) csv << kHeader << "\n";
  for (const Row& r : rows) {
    std::cout << csvRow(scene.name, r) << "\n";
    if (csv) csv << csvRow(scene.name, r) << "\n";
  }
  if (!args.plot.empty()) {
    csv.close();
    if (!surgical_sim::tools::runPlotScript(
            "contact_bench", "plot_error_vs_time.py",
            {args.csv, args.plot, scene.name + " (force vs tight Newton + CHOLMOD, same mesh)"})) {
      return 1;
    }
  }
  return 0;
}
