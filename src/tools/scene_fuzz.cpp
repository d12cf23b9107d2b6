// Scene mutator (issue 14 fuzz campaign). Usage:
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

#include "fuzz_child.h"
#include "package_dirs.h"
#include "surgical_sim/core/scene/scene_fuzz.h"

namespace ss = surgical_sim::core;
namespace fs = std::filesystem;
using surgical_sim::tools::csvField;

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
  surgical_sim::tools::FuzzArgs args;
  const std::string problem =
      surgical_sim::tools::parseFuzzArgs(argc, argv, 1000, {"--csv", "--scenes"}, "--csv", args);
  if (args.help) {
    std::cout << kUsage;
    return 0;
  }
  if (!problem.empty()) return usage(problem);
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
  std::vector<ss::SceneKind> kinds;
  for (const std::string& scene : scenes) {
    std::ifstream in(scene);
    texts.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    kinds.push_back(ss::sceneKindOf(texts.back(), scene));
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
    const ss::SceneMutant mutant = ss::mutateScene(texts[s], rng);
    const surgical_sim::tools::ChildResult child = surgical_sim::tools::runInChild(
        [&] {
          const ss::SceneTrialResult r =
              ss::trySceneMutant(mutant.text, scenes[s], kinds[s], kConstructBudgetBytes);
          return std::string(ss::toString(r.outcome)) + "\t" + (r.constructed ? "1" : "0") + "\t" +
                 r.message;
        },
        kTimeoutSeconds, kMemoryLimit);
    std::string outcome = "crash";
    std::string built = "0";
    std::string message;
    using End = surgical_sim::tools::ChildResult::End;
    if (child.end == End::TimedOut) {
      outcome = "hang";
      message = "no result after " + std::to_string(kTimeoutSeconds) + " s";
    } else if (child.end == End::Signalled) {
      message = "killed by signal " + std::to_string(child.signal);
    } else if (child.end == End::ForkFailed) {
      message = "fork failed";
    } else {
      const std::size_t tab1 = child.output.find('\t');
      const std::size_t tab2 =
          tab1 == std::string::npos ? std::string::npos : child.output.find('\t', tab1 + 1);
      if (tab2 == std::string::npos) {
        message = child.output;
      } else {
        outcome = child.output.substr(0, tab1);
        built = child.output.substr(tab1 + 1, tab2 - tab1 - 1);
        message = child.output.substr(tab2 + 1);
      }
    }
    ++counts[outcome];
    constructed += built == "1";
    slowest = std::max(slowest, child.seconds);
    csv << i << "," << csvField(fs::path(scenes[s]).filename().string()) << ","
        << csvField(mutant.mutation) << "," << outcome << "," << built << "," << child.seconds
        << "," << csvField(message) << "\n";
  }
  std::cout << "scene_fuzz: seed " << args.seed << ", " << args.count << " mutants of "
            << scenes.size() << " scenes (" << constructed << " constructed, slowest " << slowest
            << " s)\n";
  for (const auto& [outcome, n] : counts) std::printf("  %-22s %6d\n", outcome.c_str(), n);
  std::cout << "CSV: " << csv_path << "\n";
  return counts["crash"] + counts["hang"] > 0 ? 1 : 0;
}
