// connective_bench: Bosman's validation and speed cases of the rigid-node connective-tissue model
// (BENCHMARKS.md T1 / T5), headless, one CSV row per configuration.
// Usage: connective_bench <t1|t5b|speed> [--scene FILE] [--csv FILE] [--plot FILE]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "surgical_sim/bench/connective_case.h"
#include "surgical_sim/bench/tissue_case.h"
#include "surgical_sim/core/scene/scene_config.h"

namespace {

using namespace surgical_sim::bench;

constexpr const char* kTool = "connective_bench";
constexpr const char* kUsage =
    "usage: connective_bench <t1|t5b|speed> [--scene FILE] [--csv FILE] [--plot FILE]\n"
    "Bosman's cases of the rigid-node connective-tissue model (BENCHMARKS.md T1 / T5), one CSV\n"
    "row per configuration on stdout.\n"
    "  t1     steel cantilever 16 x 0.5 x 0.5 m under self-weight, trilinear weights: tip\n"
    "         deflection against 0.1501 m for cross-sections 2x2..7x7 rigid nodes (25 along)\n"
    "         and lengths 5..33 rigid nodes (5x5 across)\n"
    "  t5b    large deformation, the beam of --scene (default\n"
    "         config/bench/t5b_large_deformation.yaml): rigid nodes (trilinear and tet weights)\n"
    "         beside the scene's corotational tet4 / tet10 at its resolutions, tip error\n"
    "         against the finest tet10, DOFs and ms per linearized implicit Euler step\n"
    "  speed  ms per linearized implicit Euler step of a soft grid block clamped at one end\n"
    "         against rigid-node and sample counts (Bosman's Table 4.4 sizes included), with a\n"
    "         factorization every step and with the default factor reuse\n"
    "  --scene FILE  t5b's benchmark scene\n"
    "  --csv FILE    also write the rows to FILE\n"
    "  --plot FILE   PNG of the rows (needs --csv)\n";

int usage(const std::string& msg) {
  std::cerr << kTool << ": " << msg << "\n" << kUsage;
  return 2;
}

std::string number(double value, const char* format = "%.6g") {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

/// Prints a CSV line on stdout and into csv (when open).
void emit(std::ofstream& csv, const std::string& line) {
  std::cout << line << std::endl;
  if (csv) csv << line << "\n" << std::flush;
}

// --- T1 ---------------------------------------------------------------------------------------

constexpr double kT1Reference = 0.1501;  // m, BENCHMARKS.md T1 (fine quadratic hex FE)

int runT1(std::ofstream& csv) {
  emit(csv,
       "sweep,nodes_x,nodes_y,nodes_z,nodes,samples,dofs,tip_m,error_rel,newton_iterations,"
       "solve_ms,status");
  std::vector<std::pair<std::string, Eigen::Vector3i>> grids;
  for (int n = 2; n <= 7; ++n) grids.emplace_back("section", Eigen::Vector3i(25, n, n));
  for (int m : {5, 9, 13, 17, 25, 33}) grids.emplace_back("length", Eigen::Vector3i(m, 5, 5));
  int failures = 0;
  for (std::size_t i = 0; i < grids.size(); ++i) {
    const Eigen::Vector3i& nodes = grids[i].second;
    surgical_sim::tools::progress(kTool, surgical_sim::tools::caseCounter(i, grids.size()) + "t1 " +
                                             grids[i].first + " " + std::to_string(nodes.x()) +
                                             "x" + std::to_string(nodes.y()) + "x" +
                                             std::to_string(nodes.z()));
    const RigidNodeBeamResult r = runRigidNodeBeam(t1CantileverSpec(nodes));
    const double deflection = -r.tip;
    if (r.status != StepStatus::Ok) ++failures;
    emit(csv, grids[i].first + "," + std::to_string(nodes.x()) + "," + std::to_string(nodes.y()) +
                  "," + std::to_string(nodes.z()) + "," + std::to_string(r.nodes) + "," +
                  std::to_string(r.samples) + "," + std::to_string(r.dofs) + "," +
                  number(deflection, "%.6f") + "," +
                  number((deflection - kT1Reference) / kT1Reference, "%.5f") + "," +
                  std::to_string(r.newton_iterations) + "," + number(r.solve_ms, "%.1f") + "," +
                  toString(r.status));
  }
  return failures;
}

// --- T5(b) ------------------------------------------------------------------------------------

struct T5bRow {
  std::string model, element;
  Eigen::Vector3i cells;
  int nodes = 0, samples = 0, dofs = 0;
  int newton_iterations = -1;  ///< summed over the load increments; -1: not a Newton row
  double tip = std::nan(""), residual = std::nan(""), ms_per_step = std::nan("");
  std::string status;
};

/// Corotational tet FE of the scene at one resolution: the quasi-static tip (the scene's
/// measure) and, from a second run, the mean time of its linearized implicit Euler steps after
/// the first.
T5bRow tetRow(const BenchmarkScene& scene, const Eigen::Vector3i& cells, ElementType type) {
  CaseSpec spec;
  spec.resolution = cells;
  spec.element_type = type;
  spec.model = ModelKind::Corotational;
  spec.integrator = IntegratorKind::QuasiStatic;
  spec.solver = SolverKind::Cholmod;
  const CaseResult statics = runTissueCase(scene, spec);
  BenchmarkScene dynamic = scene;
  dynamic.steps = 4;
  dynamic.time_step = 0.01;
  spec.integrator = IntegratorKind::ImplicitEulerLinearized;
  const CaseResult timing = runTissueCase(dynamic, spec);
  T5bRow row;
  row.model = "corotational";
  row.element = type == ElementType::Tet10 ? "tet10" : "tet4";
  row.cells = cells;
  row.nodes = statics.nodes;
  row.samples = statics.elements;
  row.dofs = statics.dofs;
  row.status = toString(statics.status);
  if (statics.status == StepStatus::Ok) row.tip = statics.measured;
  row.ms_per_step = timing.ms_after_first;
  return row;
}

T5bRow rigidNodeRow(const BenchmarkScene& scene, const Eigen::Vector3i& cells,
                    RigidNodeWeights weights) {
  RigidNodeBeamSpec spec;
  spec.size = scene.mesh.size;
  spec.material = scene.material;
  spec.gravity = scene.gravity;
  spec.component = scene.measure.component;
  spec.cells = cells;
  spec.weights = weights;
  spec.load_steps = scene.steps;
  spec.relative_tolerance = 1e-8;
  spec.timed_steps = 3;
  const RigidNodeBeamResult r = runRigidNodeBeam(spec);
  T5bRow row;
  row.model = "rigid_node";
  row.element = rigidNodeWeightsName(weights);
  row.cells = cells;
  row.nodes = r.nodes;
  row.samples = r.samples;
  row.dofs = r.dofs;
  row.tip = r.tip;
  row.residual = r.residual;
  row.newton_iterations = r.newton_iterations;
  row.ms_per_step = r.ms_per_step;
  row.status = toString(r.status);
  return row;
}

int runT5b(const std::string& scene_path, std::ofstream& csv) {
  const BenchmarkScene scene = loadBenchmarkScene(scene_path);
  if (scene.mesh.generator != "beam")
    throw std::invalid_argument("scene " + scene_path + ": t5b needs mesh.generator beam");
  applyBenchThreads(scene);
  std::vector<T5bRow> rows;
  const std::size_t total = scene.resolutions.size() * (2 + scene.element_types.size());
  for (const Eigen::Vector3i& cells : scene.resolutions) {
    const std::string label = std::to_string(cells.x()) + "x" + std::to_string(cells.y()) + "x" +
                              std::to_string(cells.z());
    for (RigidNodeWeights weights : {RigidNodeWeights::Trilinear, RigidNodeWeights::Tet}) {
      surgical_sim::tools::progress(kTool, surgical_sim::tools::caseCounter(rows.size(), total) +
                                               "rigid nodes, " + rigidNodeWeightsName(weights) +
                                               " weights, " + label + " cells");
      rows.push_back(rigidNodeRow(scene, cells, weights));
    }
    for (ElementType type : scene.element_types) {
      surgical_sim::tools::progress(kTool, surgical_sim::tools::caseCounter(rows.size(), total) +
                                               "corotational " + toString(type) + ", " + label +
                                               " cells");
      rows.push_back(tetRow(scene, cells, type));
    }
  }
  // Reference: the tet10 row with the most DOFs that converged.
  double reference = std::nan("");
  int reference_dofs = 0;
  for (const T5bRow& row : rows)
    if (row.element == "tet10" && std::isfinite(row.tip) && row.dofs > reference_dofs) {
      reference = row.tip;
      reference_dofs = row.dofs;
    }
  emit(csv,
       "case,model,element,cells_x,cells_y,cells_z,nodes,samples,dofs,tip_m,reference_m,"
       "error_rel,residual,newton_iterations,ms_per_step,status");
  int failures = 0;
  for (const T5bRow& row : rows) {
    if (row.status != "ok") ++failures;
    const std::string cells = std::to_string(row.cells.x()) + "," + std::to_string(row.cells.y()) +
                              "," + std::to_string(row.cells.z());
    emit(csv, scene.name + "_" + row.model + "_" + row.element + "_" +
                  std::to_string(row.cells.x()) + "x" + std::to_string(row.cells.y()) + "x" +
                  std::to_string(row.cells.z()) + "," + row.model + "," + row.element + "," +
                  cells + "," + std::to_string(row.nodes) + "," + std::to_string(row.samples) +
                  "," + std::to_string(row.dofs) + "," + number(row.tip, "%.6f") + "," +
                  number(reference, "%.6f") + "," +
                  number(std::abs(row.tip - reference) / std::abs(reference), "%.5f") + "," +
                  number(row.residual, "%.2g") + "," +
                  (row.newton_iterations < 0 ? "" : std::to_string(row.newton_iterations)) + "," +
                  number(row.ms_per_step, "%.3f") + "," + row.status);
  }
  return failures;
}

// --- speed ------------------------------------------------------------------------------------

int runSpeed(std::ofstream& csv) {
  emit(csv,
       "nodes_x,nodes_y,nodes_z,nodes,samples,dofs,refresh_interval,factorizations,ms_per_step,"
       "cpu_ms_per_step,forces_ms,factor_ms,linear_solve_ms,linear_iterations,bosman_ms,status");
  // Bosman's Table 4.4 (Core i7, LDL^T) by rigid-node count [ms].
  auto bosman = [](int nodes) {
    return nodes == 48 ? 27.0 : nodes == 216 ? 177.0 : nodes == 512 ? 753.0 : std::nan("");
  };
  const std::vector<Eigen::Vector3i> grids = {Eigen::Vector3i(3, 3, 3), Eigen::Vector3i(4, 4, 3),
                                              Eigen::Vector3i(5, 5, 4), Eigen::Vector3i(6, 6, 6),
                                              Eigen::Vector3i(8, 8, 8)};
  // Each size twice: a direct solve every step, and the default factor reuse.
  const int refresh_intervals[] = {1, RigidNodeImplicitEulerSettings{}.refresh_interval};
  int failures = 0;
  for (std::size_t i = 0; i < grids.size(); ++i) {
    const Eigen::Vector3i& nodes = grids[i];
    surgical_sim::tools::progress(kTool, surgical_sim::tools::caseCounter(i, grids.size()) +
                                             "speed, " + std::to_string(nodes.prod()) +
                                             " rigid nodes");
    for (const int refresh_interval : refresh_intervals) {
      RigidNodeBeamSpec spec;
      spec.size = 0.01 * (nodes - Eigen::Vector3i::Ones()).cast<double>();
      spec.material = Material::create(20e3, 0.4, 1000.0);
      spec.cells = nodes - Eigen::Vector3i::Ones();
      spec.load_steps = 0;
      spec.timed_steps = 20;
      spec.integrator.refresh_interval = refresh_interval;
      const RigidNodeBeamResult r = runRigidNodeBeam(spec);
      if (r.status != StepStatus::Ok) ++failures;
      emit(csv, std::to_string(nodes.x()) + "," + std::to_string(nodes.y()) + "," +
                    std::to_string(nodes.z()) + "," + std::to_string(r.nodes) + "," +
                    std::to_string(r.samples) + "," + std::to_string(r.dofs) + "," +
                    std::to_string(refresh_interval) + "," + std::to_string(r.factorizations) +
                    "," + number(r.ms_per_step, "%.3f") + "," + number(r.cpu_ms_per_step, "%.3f") +
                    "," + number(r.forces_ms, "%.3f") + "," + number(r.factor_ms, "%.3f") + "," +
                    number(r.linear_solve_ms, "%.3f") + "," + number(r.linear_iterations, "%.1f") +
                    "," + number(bosman(r.nodes), "%.0f") + "," + toString(r.status));
    }
  }
  return failures;
}

}  // namespace

int main(int argc, char** argv) {
  if (surgical_sim::tools::wantsHelp(argc, argv)) {
    std::cout << kUsage;
    return 0;
  }
  std::string which, scene, csv_path, plot_path;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--scene" || arg == "--csv" || arg == "--plot") && i + 1 < argc) {
      (arg == "--scene" ? scene : arg == "--csv" ? csv_path : plot_path) = argv[++i];
    } else if (!arg.empty() && arg[0] == '-') {
      return usage("unknown option " + arg);
    } else if (which.empty()) {
      which = arg;
    } else {
      return usage("more than one case given");
    }
  }
  if (which != "t1" && which != "t5b" && which != "speed")
    return usage(which.empty() ? "no case given" : "unknown case " + which);
  if (!scene.empty() && which != "t5b") return usage("--scene is for t5b only");
  if (!plot_path.empty() && csv_path.empty()) return usage("--plot needs --csv");
  if (scene.empty()) scene = surgical_sim::tools::configDir() + "/bench/t5b_large_deformation.yaml";

  std::ofstream csv;
  if (!surgical_sim::tools::openCsv(kTool, csv_path, csv)) return 1;
  int failures = 0;
  try {
    failures = which == "t1" ? runT1(csv) : which == "t5b" ? runT5b(scene, csv) : runSpeed(csv);
  } catch (const std::exception& e) {
    std::cerr << kTool << ": " << e.what() << "\n";
    return 1;
  }
  if (!plot_path.empty()) {
    csv.close();
    if (!surgical_sim::tools::runPlotScript(kTool, "plot_connective.py",
                                            {which, csv_path, plot_path}))
      return 1;
  }
  return failures == 0 ? 0 : 1;
}
