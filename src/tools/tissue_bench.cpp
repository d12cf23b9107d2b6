// tissue_bench: runs a tissue scene's sweep headless (no roscore) and reports error against run
// time. Usage: tissue_bench <scene.yaml> [--csv FILE] [--plot FILE]
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

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
  std::string scene_path, csv_path, plot_path;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--csv" || arg == "--plot") && i + 1 < argc) {
      (arg == "--csv" ? csv_path : plot_path) = argv[++i];
    } else if (!arg.empty() && arg[0] == '-') {
      return usage(("unknown option " + arg).c_str());
    } else if (scene_path.empty()) {
      scene_path = arg;
    } else {
      return usage("more than one scene given");
    }
  }
  if (scene_path.empty()) return usage("no scene given");

  SceneConfig scene;
  try {
    scene = loadSceneConfig(scene_path);
  } catch (const std::exception& e) {
    std::cerr << "tissue_bench: " << e.what() << "\n";
    return 1;
  }
  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    if (!csv) {
      std::cerr << "tissue_bench: cannot write " << csv_path << "\n";
      return 1;
    }
    csv << caseCsvHeader() << "\n";
  }
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
      std::cerr << "tissue_bench: case " << spec.model << "/" << spec.integrator << "/"
                << spec.solver << " failed to set up: " << e.what() << "\n";
    }
  }
  if (!plot_path.empty()) {
    if (csv_path.empty()) return usage("--plot needs --csv");
    csv.close();
    const std::string cmd = std::string("/usr/bin/python3 '") + SURGICAL_SIM_SCRIPTS_DIR +
                            "/plot_error_vs_time.py' '" + csv_path + "' '" + plot_path + "' '" +
                            scene.name + "'";
    if (std::system(cmd.c_str()) != 0) {
      std::cerr << "tissue_bench: plotting failed (" << cmd << ")\n";
      return 1;
    }
  }
  return failures == 0 ? 0 : 1;
}
