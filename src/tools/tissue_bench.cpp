// tissue_bench: runs a tissue scene's sweep headless (no roscore) and reports error against run
// time. Usage: tissue_bench <scene.yaml> [--csv FILE] [--plot FILE]
#include <cmath>
#include <fstream>
#include <iostream>
#include <string>

#include "bench_cli.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_case.h"

namespace {

int usage(const char* msg) {
  std::cerr << "tissue_bench: " << msg << "\n"
            << "usage: tissue_bench <scene.yaml> [--csv FILE] [--plot FILE]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace surgical_sim::core;
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
  for (const CaseSpec& spec : expandSweep(scene)) {
    try {
      const CaseResult r = runTissueCase(scene, spec);
      const std::string row = caseCsvRow(scene.name, r);
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
