// Scene mutator (robustness campaign). Usage:
//   scene_fuzz --seed S --count N --csv FILE [--scenes DIR]
// Mutates the shipped scenes (DIR/*.yaml, default config/scenes and config/bench) N (>= 1000)
// times, taking them in turn, and runs each mutant in a child process (20 s, 4 GB address
// space): parseRuntimeScene() or parseBenchmarkScene(), then a TissueSimulation for mutants that
// parse and whose first case is estimated at most 256 MB (larger ones are accepted without
// construction, keeping the campaign bounded). Prints the count of each outcome (accepted,
// rejected_naming_key, rejected_without_key, crash, hang) and writes FILE, one row per mutant:
// index, scene, mutation, outcome, constructed, seconds, message. Exit code 1 on any crash or hang.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "package_dirs.h"
#include "surgical_sim/bench/fuzz_child.h"
#include "surgical_sim/bench/scene_fuzz.h"

namespace bench = surgical_sim::bench;
namespace fs = std::filesystem;
using bench::csvField;

namespace {

constexpr const char* kUsage =
    "usage: scene_fuzz --seed S --count N --csv FILE [--scenes DIR]\n"
    "  mutates the shipped scenes N >= 1000 times, parses (and constructs) each mutant in a\n"
    "  child process and writes FILE (index,scene,mutation,outcome,constructed,seconds,message)\n";
constexpr double kTimeoutSeconds = 20.0;  ///< beyond this a mutant counts as a hang
constexpr rlim_t kMemoryLimit = rlim_t{4} << 30;
constexpr double kConstructBudgetBytes = 256e6;

int usage(const std::string& error) {
  std::cerr << "scene_fuzz: " << error << "\n" << kUsage;
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  bench::FuzzArgs args;
  if (const auto exit = bench::fuzzCommandLineExit("scene_fuzz", kUsage, argc, argv, 1000,
                                                   {"--csv", "--scenes"}, "--csv", args))
    return *exit;
  const std::string csv_path = args.text["--csv"];
  const std::string config = surgical_sim::tools::configDir();
  const std::vector<std::string> scene_dirs =
      args.text.count("--scenes") ? std::vector<std::string>{args.text["--scenes"]}
                                  : std::vector<std::string>{config + "/scenes", config + "/bench"};
  std::vector<std::string> scenes;
  for (const std::string& dir : scene_dirs)
    if (fs::is_directory(dir))
      for (const auto& entry : fs::directory_iterator(dir))
        if (entry.path().extension() == ".yaml") scenes.push_back(entry.path().string());
  std::sort(scenes.begin(), scenes.end());
  if (scenes.empty()) return usage("no *.yaml scenes in " + scene_dirs.front());
  std::vector<std::string> texts;
  std::vector<bench::SceneKind> kinds;
  for (const std::string& scene : scenes) {
    std::ifstream in(scene);
    texts.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    kinds.push_back(bench::sceneKindOf(texts.back(), scene));
  }
  std::ofstream csv(csv_path);
  if (!csv) return usage("cannot write " + csv_path);
  csv << "index,scene,mutation,outcome,constructed,seconds,message\n";

  std::map<std::string, int> counts;
  for (const char* o : {"accepted", "rejected_naming_key", "rejected_without_key", "crash", "hang"})
    counts[o] = 0;
  int constructed = 0;
  double slowest = 0.0;
  for (int i = 0; i < static_cast<int>(args.count); ++i) {
    const std::size_t s = static_cast<std::size_t>(i) % scenes.size();
    std::mt19937 rng(static_cast<unsigned>(args.seed) + static_cast<unsigned>(i));
    const bench::SceneMutant mutant = bench::mutateScene(texts[s], rng);
    const bench::ChildResult child = bench::runInChild(
        [&] {
          const bench::SceneTrialResult r =
              bench::trySceneMutant(mutant.text, scenes[s], kinds[s], kConstructBudgetBytes);
          return std::string(bench::toString(r.outcome)) + "\t" + (r.constructed ? "1" : "0") +
                 "\t" + r.message;
        },
        kTimeoutSeconds, kMemoryLimit);
    const std::vector<std::string> fields = bench::trialFields(child, kTimeoutSeconds, 3);
    const std::string& outcome = fields[0];
    const int built = fields[1] == "1" ? 1 : 0;
    ++counts[outcome];
    constructed += built;
    slowest = std::max(slowest, child.seconds);
    csv << i << "," << csvField(fs::path(scenes[s]).filename().string()) << ","
        << csvField(mutant.mutation) << "," << outcome << "," << built << "," << child.seconds
        << "," << csvField(fields[2]) << "\n";
  }
  std::cout << "scene_fuzz: seed " << args.seed << ", " << args.count << " mutants of "
            << scenes.size() << " scenes (" << constructed << " constructed, slowest " << slowest
            << " s)\n";
  for (const auto& [outcome, n] : counts) std::printf("  %-22s %6d\n", outcome.c_str(), n);
  std::cout << "CSV: " << csv_path << "\n";
  return counts["crash"] + counts["hang"] > 0 ? 1 : 0;
}
