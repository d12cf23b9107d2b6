// tool_fuzz: S1 robustness campaign, in-process and in lockstep. Drives a scene's tools with
// hostile random pose streams (runToolFuzzSequence) and prints one table row per sequence and a
// total; optionally writes the rows as CSV. Progress goes to stderr.

#include <cstdlib>
#include <exception>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "package_dirs.h"
#include "surgical_sim/bench/tool_fuzz.h"
#include "surgical_sim/core/scene/multi_body_simulation.h"
#include "surgical_sim/core/scene/scene_config.h"

namespace {

using surgical_sim::bench::ToolFuzzOutcome;

constexpr const char* kUsage =
    "usage: tool_fuzz [--scene FILE] [--sequences N] [--steps N] [--seed S] [--csv FILE]\n"
    "                 [--max-force N] [--bad-pose-rate P] [--cut-rate P]\n"
    "  Drives the scene's tools with random hostile pose streams in lockstep with the\n"
    "  simulation (within 10 cm of the tissue, up to 2 m/s, dives through the body, 1 m\n"
    "  teleports and back, random orientations, jaw toggles, malformed poses that the node's\n"
    "  pose check must reject). Sequence i uses seed S + i. A multi-body scene (bodies:\n"
    "  FE organs and connective layers) is driven the same way.\n"
    "  --scene FILE       scene YAML (default config/scenes/palpation.yaml)\n"
    "  --sequences N      number of sequences (default 10)\n"
    "  --steps N          steps per sequence (default 1000 = 10 s at dt 0.01 s)\n"
    "  --seed S           base seed (default 1)\n"
    "  --csv FILE         one row per sequence\n"
    "  --max-force N      force bound for every tool [N] (default: the scene's tools[].max_force\n"
    "                     when the build knows it; else forces are only reported)\n"
    "  --bad-pose-rate P  malformed poses per step and tool (default 0.02)\n"
    "  --cut-rate P       blade sweeps per step through the first tool's tip region (default 0;\n"
    "                     single-body scenes): counts the sweeps, the steps they changed the\n"
    "                     topology in, the refused ones, the largest mass error and the\n"
    "                     surfaces left open (a mass error or an open surface fails)\n";

/// Largest relative change of the total mass that cuts may cause (they conserve it) [-].
constexpr double kMassTolerance = 1e-12;

/// Status names that always get a column, in this order; others seen are appended.
const std::vector<std::string> kStatusColumns = {"ok",         "not_converged", "solver_failed",
                                                 "non_finite", "blow_up",       "contact_limited"};

struct Args {
  std::string scene = surgical_sim::tools::configDir() + "/scenes/palpation.yaml";
  int sequences = 10;
  int steps = 1000;
  unsigned seed = 1;
  std::string csv;
  double max_force = 0.0;  ///< 0: from the scene
  double bad_pose_rate = 0.02;
  double cut_rate = 0.0;
};

/// Parses argv; returns "" or what is wrong. Sets help when --help was given.
std::string parse(int argc, char** argv, Args& a, bool& help) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      help = true;
      return "";
    }
    if (i + 1 >= argc) return "option " + arg + " needs a value (or is unknown)";
    const std::string value = argv[++i];
    char* end = nullptr;
    if (arg == "--scene") {
      a.scene = value;
      continue;
    }
    if (arg == "--csv") {
      a.csv = value;
      continue;
    }
    static const std::set<std::string> numeric = {"--sequences", "--steps",         "--seed",
                                                  "--max-force", "--bad-pose-rate", "--cut-rate"};
    if (!numeric.count(arg)) return "unknown option " + arg + " (see --help)";
    const double number = std::strtod(value.c_str(), &end);
    if (end == value.c_str() || *end != '\0') return arg + " needs a number, got '" + value + "'";
    if (arg == "--sequences" && number >= 1)
      a.sequences = static_cast<int>(number);
    else if (arg == "--steps" && number >= 1)
      a.steps = static_cast<int>(number);
    else if (arg == "--seed" && number >= 0)
      a.seed = static_cast<unsigned>(number);
    else if (arg == "--max-force" && number > 0)
      a.max_force = number;
    else if (arg == "--bad-pose-rate" && number >= 0 && number <= 1)
      a.bad_pose_rate = number;
    else if (arg == "--cut-rate" && number >= 0 && number <= 1)
      a.cut_rate = number;
    else
      return "unknown option or value out of range: " + arg + " " + value;
  }
  return "";
}

std::vector<std::string> statusColumns(const ToolFuzzOutcome& total) {
  std::vector<std::string> cols = kStatusColumns;
  const std::set<std::string> known(cols.begin(), cols.end());
  for (const auto& [status, n] : total.status_steps)
    if (!known.count(status)) cols.push_back(status);
  return cols;
}

int count(const ToolFuzzOutcome& o, const std::string& status) {
  const auto it = o.status_steps.find(status);
  return it == o.status_steps.end() ? 0 : it->second;
}

void printRow(std::ostream& out, const std::string& label, const ToolFuzzOutcome& o,
              const std::vector<std::string>& statuses) {
  out << std::left << std::setw(9) << label << std::right << std::setw(7) << o.steps
      << std::setw(11) << o.non_finite_steps << std::setw(9) << o.contact_steps << std::setw(12)
      << std::setprecision(5) << o.max_force << std::setw(11) << o.over_bound_steps << std::setw(11)
      << o.limited_but_ok_steps << std::setw(10) << o.rejected_poses << std::setw(10)
      << o.bad_poses_accepted << std::setw(9) << o.teleports << std::setw(9) << o.grasp_toggles
      << std::setw(12) << std::fixed << std::setprecision(3)
      << (o.steps ? 1e3 * o.wall_seconds / o.steps : 0.0) << std::defaultfloat;
  for (const std::string& s : statuses) out << "  " << s << "=" << count(o, s);
  out << "\n";
}

/// The total as one line of outcome=count pairs (the format scripts/robustness collects).
void printCounts(std::ostream& out, const ToolFuzzOutcome& o,
                 const std::vector<std::string>& statuses) {
  out << "tools     sequences=" << o.sequences << "  steps=" << o.steps
      << "  non_finite=" << o.non_finite_steps << "  contact_steps=" << o.contact_steps
      << "  max_force_N=" << o.max_force << "  over_bound=" << o.over_bound_steps
      << "  limited_but_ok=" << o.limited_but_ok_steps << "  rejected_poses=" << o.rejected_poses
      << "  bad_poses_accepted=" << o.bad_poses_accepted << "  teleports=" << o.teleports
      << "  grasp_toggles=" << o.grasp_toggles;
  for (const std::string& s : statuses) out << "  status_" << s << "=" << count(o, s);
  if (o.cuts.sweeps > 0)
    out << "  cut_sweeps=" << o.cuts.sweeps << "  cut_steps=" << o.cuts.changed_steps
        << "  refused_cut_steps=" << o.cuts.refused_steps
        << "  max_mass_error=" << o.cuts.max_mass_error
        << "  open_surfaces=" << o.cuts.open_surfaces;
  out << "  ms_per_step=" << (o.steps ? 1e3 * o.wall_seconds / o.steps : 0.0) << "\n";
}

void printHeader(std::ostream& out) {
  out << std::left << std::setw(9) << "sequence" << std::right << std::setw(7) << "steps"
      << std::setw(11) << "nonfinite" << std::setw(9) << "contact" << std::setw(12) << "max_f[N]"
      << std::setw(11) << "over_bound" << std::setw(11) << "lim_but_ok" << std::setw(10)
      << "rejected" << std::setw(10) << "bad_acc" << std::setw(9) << "telep" << std::setw(9)
      << "grasp" << std::setw(12) << "ms/step"
      << "  steps per status\n";
}

void writeCsv(std::ostream& csv, const std::vector<ToolFuzzOutcome>& rows, unsigned seed,
              const std::vector<std::string>& statuses, const std::string& bound) {
  csv << "sequence,seed,steps,non_finite_steps,contact_steps,max_force_N,force_bound_N,over_bound_"
         "steps,"
         "limited_but_ok_steps,accepted_poses,rejected_poses,bad_poses_accepted,teleports,"
         "grasp_toggles,max_abs_energy_J,max_energy_rise_J,ms_per_step,cut_sweeps,cut_steps,"
         "refused_cut_steps,max_mass_error,open_surfaces";
  for (const std::string& s : statuses) csv << ",status_" << s;
  csv << "\n" << std::setprecision(9);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ToolFuzzOutcome& o = rows[i];
    csv << i << "," << seed + i << "," << o.steps << "," << o.non_finite_steps << ","
        << o.contact_steps << "," << o.max_force << "," << bound << "," << o.over_bound_steps << ","
        << o.limited_but_ok_steps << "," << o.accepted_poses << "," << o.rejected_poses << ","
        << o.bad_poses_accepted << "," << o.teleports << "," << o.grasp_toggles << ","
        << o.max_abs_energy << "," << o.max_energy_rise << "," << 1e3 * o.wall_seconds / o.steps
        << "," << o.cuts.sweeps << "," << o.cuts.changed_steps << "," << o.cuts.refused_steps << ","
        << o.cuts.max_mass_error << "," << o.cuts.open_surfaces;
    for (const std::string& s : statuses) csv << "," << count(o, s);
    csv << "\n";
  }
}

}  // namespace

/// Runs args.sequences sequences on sim (a scene of `nodes` organ nodes), prints the table and
/// writes the CSV; the exit code: 0 clean, 3 a violation.
template <typename Simulation>
int fuzz(const Args& args, const surgical_sim::bench::ToolFuzzSettings& settings, Simulation& sim,
         int nodes) {
  std::ofstream csv;
  if (!surgical_sim::tools::openCsv("tool_fuzz", args.csv, csv)) return 1;
  std::ostringstream bound;
  for (std::size_t i = 0; i < settings.force_bounds.size(); ++i)
    bound << (i ? ";" : "")
          << (settings.force_bounds[i] ? std::to_string(*settings.force_bounds[i]) : "none");

  std::cerr << "tool_fuzz: scene " << sim.scene().name << " (" << nodes << " nodes, "
            << sim.numTools() << " tool(s), force bound " << bound.str() << " N), "
            << args.sequences << " x " << args.steps << " steps, seed " << args.seed << "\n";
  std::vector<ToolFuzzOutcome> rows;
  ToolFuzzOutcome total;
  for (int s = 0; s < args.sequences; ++s) {
    std::mt19937 rng(args.seed + static_cast<unsigned>(s));
    rows.push_back(surgical_sim::bench::runToolFuzzSequence(sim, settings, rng));
    total.merge(rows.back());
    std::cerr << "tool_fuzz: sequence " << s + 1 << "/" << args.sequences << ": "
              << rows.back().non_finite_steps << " non-finite, max force " << rows.back().max_force
              << " N, " << 1e3 * rows.back().wall_seconds / rows.back().steps << " ms/step\n";
  }
  const std::vector<std::string> statuses = statusColumns(total);
  printHeader(std::cout);
  for (std::size_t i = 0; i < rows.size(); ++i)
    printRow(std::cout, std::to_string(i), rows[i], statuses);
  printRow(std::cout, "total", total, statuses);
  printCounts(std::cout, total, statuses);
  if (csv.is_open()) writeCsv(csv, rows, args.seed, statuses, bound.str());
  const bool clean = total.non_finite_steps == 0 && total.over_bound_steps == 0 &&
                     total.limited_but_ok_steps == 0 && total.bad_poses_accepted == 0 &&
                     total.cuts.max_mass_error <= kMassTolerance && total.cuts.open_surfaces == 0;
  return clean ? 0 : 3;
}

int main(int argc, char** argv) {
  Args args;
  bool help = false;
  const std::string problem = parse(argc, argv, args, help);
  if (help) {
    std::cout << kUsage;
    return 0;
  }
  if (!problem.empty()) {
    std::cerr << "tool_fuzz: " << problem << "\n" << kUsage;
    return 2;
  }
  try {
    const surgical_sim::core::RuntimeScene scene = surgical_sim::core::loadRuntimeScene(args.scene);
    if (scene.tools.empty()) {
      std::cerr << "tool_fuzz: scene " << args.scene << " has no tools\n";
      return 1;
    }
    surgical_sim::bench::ToolFuzzSettings settings;
    settings.steps = args.steps;
    settings.bad_pose_rate = args.bad_pose_rate;
    settings.cut_rate = args.cut_rate;
    settings.force_bounds = surgical_sim::bench::sceneForceBounds(scene);
    if (args.max_force > 0.0)
      for (auto& b : settings.force_bounds) b = args.max_force;
    if (scene.bodies.empty()) {
      surgical_sim::core::TissueSimulation sim(scene);
      return fuzz(args, settings, sim, sim.mesh().numNodes());
    }
    surgical_sim::core::MultiBodySimulation sim(scene);
    int nodes = 0;
    for (int b = 0; b < sim.numBodies(); ++b) nodes += sim.bodyMesh(b).numNodes();
    return fuzz(args, settings, sim, nodes);
  } catch (const std::exception& e) {
    std::cerr << "tool_fuzz: " << e.what() << "\n";
    return 1;
  }
}
