// tissue_bench: runs a tissue scene's sweep headless (no roscore) and reports error against run
// time. Usage: tissue_bench <scene.yaml> [--csv FILE] [--plot FILE]
#include <cmath>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "surgical_sim/bench/tissue_case.h"
#include "surgical_sim/core/scene/scene_config.h"

namespace {

constexpr const char* kUsage =
    "usage: tissue_bench <scene.yaml> [--csv FILE] [--plot FILE]\n"
    "Runs every case of a benchmark scene's sweep headless and reports its error against run\n"
    "time (one CSV row per case on stdout).\n"
    "  --csv FILE   also write the rows to FILE\n"
    "  --plot FILE  error against ms per step (PNG; needs --csv)\n";

int usage(const char* msg) {
  std::cerr << "tissue_bench: " << msg << "\n" << kUsage;
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace surgical_sim::bench;
  if (surgical_sim::tools::wantsHelp(argc, argv)) {
    std::cout << kUsage;
    return 0;
  }
  surgical_sim::tools::SceneBenchArgs args;
  const std::string error = surgical_sim::tools::parseSceneBenchArgs(argc, argv, args);
  if (!error.empty()) return usage(error.c_str());

  BenchmarkScene scene;
  try {
    scene = loadBenchmarkScene(args.scene);
  } catch (const std::exception& e) {
    std::cerr << "tissue_bench: " << e.what() << "\n";
    return 1;
  }
  std::ofstream csv;
  if (!surgical_sim::tools::openCsv("tissue_bench", args.csv, csv)) return 1;
  if (csv) csv << caseCsvHeader() << "\n";
  std::cout << caseCsvHeader() << std::endl;
  int failures = 0;
  const std::vector<CaseSpec> cases = expandSweep(scene);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const CaseSpec& spec = cases[i];
    surgical_sim::tools::progress(
        "tissue_bench", surgical_sim::tools::caseCounter(i, cases.size()) + modelName(spec.model) +
                            "/" + integratorName(spec.integrator) + "/" + solverName(spec.solver) +
                            ", resolution " + std::to_string(spec.resolution.x()));
    try {
      const CaseResult r = runTissueCase(scene, spec);
      const std::string row = caseCsvRow(caseLabel(scene, spec), r);
      std::cout << row << std::endl;
      if (csv) csv << row << "\n" << std::flush;
    } catch (const std::exception& e) {
      ++failures;
      std::cerr << "tissue_bench: case " << modelName(spec.model) << "/"
                << integratorName(spec.integrator) << "/" << solverName(spec.solver)
                << " failed to set up: " << e.what() << "\n";
    }
  }
  if (!args.plot.empty()) {
    csv.close();
    if (!surgical_sim::tools::runPlotScript("tissue_bench", "plot_error_vs_time.py",
                                            {args.csv, args.plot, scene.name})) {
      return 1;
    }
  }
  return failures == 0 ? 0 : 1;
}
