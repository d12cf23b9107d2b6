// tissue_bench: runs a tissue scene's sweep headless (no roscore) and reports error against run
// time, the step's phase split and the peak resident memory, each case in its own child process.
// Usage: tissue_bench <scene.yaml> [--csv FILE] [--plot FILE]
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "surgical_sim/bench/tissue_case.h"
#include "surgical_sim/core/scene/scene_config.h"

namespace {

constexpr const char* kUsage =
    "usage: tissue_bench <scene.yaml> [--csv FILE] [--plot FILE]\n"
    "Runs every case of a benchmark scene's sweep headless, each in its own child process, and\n"
    "reports its error against run time, step time p99, first step, phase split (forces,\n"
    "assembly, factorization, linear solve), linear iterations, achieved GFLOP/s and GB/s per\n"
    "phase and peak resident memory (one CSV row per case on stdout).\n"
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
  // self_reference scenes: one reference run per reference group, mesh and model, in a child
  // process; the case children inherit its positions.
  std::map<std::string, Eigen::VectorXd> references;
  for (const BenchmarkVariant& variant : benchVariants(scene)) {
    const bool self_reference = variant.scene.measure.type == "self_reference";
    const std::vector<CaseSpec> cases = expandSweep(variant.scene);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const CaseSpec& spec = cases[i];
      const std::string what = (variant.name.empty() ? "" : variant.name + ": ") +
                               modelName(spec.model) + "/" + integratorName(spec.integrator) + "/" +
                               solverName(spec.solver);
      surgical_sim::tools::progress("tissue_bench",
                                    surgical_sim::tools::caseCounter(i, cases.size()) + what +
                                        ", resolution " + std::to_string(spec.resolution.x()));
      const Eigen::VectorXd* reference_x = nullptr;
      if (self_reference) {
        const std::string key =
            referenceGroup(variant) + "/" + selfReferenceKey(variant.scene, spec);
        if (references.count(key) == 0) {
          surgical_sim::tools::progress("tissue_bench", "reference for " + key);
          const std::optional<std::string> bytes =
              surgical_sim::tools::runCaseInChild("tissue_bench", "reference for " + key, [&] {
                applyBenchThreads(variant.scene);
                const Eigen::VectorXd x = selfReferencePositions(variant.scene, spec);
                return std::string(reinterpret_cast<const char*>(x.data()),
                                   sizeof(double) * static_cast<std::size_t>(x.size()));
              });
          Eigen::VectorXd& x = references[key];  // stays empty when the reference failed
          if (bytes) {
            x.resize(static_cast<Eigen::Index>(bytes->size() / sizeof(double)));
            std::memcpy(x.data(), bytes->data(),
                        sizeof(double) * static_cast<std::size_t>(x.size()));
          }
        }
        reference_x = &references[key];
        if (reference_x->size() == 0) ++failures;  // the case still runs, its error_rel NaN
      }
      const std::optional<std::string> row =
          surgical_sim::tools::runCaseInChild("tissue_bench", "case " + what, [&] {
            applyBenchThreads(variant.scene);
            return caseCsvRow(caseLabel(variant.scene, spec),
                              runTissueCase(variant.scene, spec, reference_x), variant.name);
          });
      if (!row) {
        ++failures;
        continue;
      }
      std::cout << *row << std::endl;
      if (csv) csv << *row << "\n" << std::flush;
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
