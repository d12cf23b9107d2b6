// Mesh corruptor (robustness campaign). Usage:
//   mesh_fuzz --seed S --count N --out DIR [--sources DIR]
// Derives N (>= 200) corrupted files from the shipped meshes (<sources>/config/meshes/*.msh and
// <sources>/test/data/*.msh, *.obj, *.stl; default sources: this package), writes them into
// DIR/mutants and loads each in a child process (60 s, 4 GB address space). Prints the count of
// each outcome (loaded, rejected_with_message, warned_repair, crash, hang) and writes
// DIR/mesh_fuzz.csv, one row per file: index, source, mutation, outcome, message.
// Exit code 1 if any file crashed or hung.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "package_dirs.h"
#include "surgical_sim/bench/fuzz_child.h"
#include "surgical_sim/bench/mesh_fuzz.h"

namespace bench = surgical_sim::bench;
namespace fs = std::filesystem;

namespace {

constexpr const char* kUsage =
    "usage: mesh_fuzz --seed S --count N --out DIR [--sources DIR]\n"
    "  corrupts the shipped meshes N >= 200 times, loads each mutant in a child process and\n"
    "  writes DIR/mesh_fuzz.csv (index,source,mutation,outcome,message)\n";
constexpr double kTimeoutSeconds = 60.0;
constexpr rlim_t kMemoryLimit = rlim_t{4} << 30;

int usage(const std::string& error) {
  std::cerr << "mesh_fuzz: " << error << "\n" << kUsage;
  return 2;
}

std::vector<std::string> shippedMeshes(const fs::path& root) {
  std::vector<std::string> files;
  for (const fs::path& dir : {root / "config/meshes", root / "test/data"}) {
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string ext = entry.path().extension().string();
      if (ext == ".msh" || ext == ".obj" || ext == ".stl") files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

int main(int argc, char** argv) {
  bench::FuzzArgs args;
  if (const auto exit = bench::fuzzCommandLineExit("mesh_fuzz", kUsage, argc, argv, 200,
                                                   {"--out", "--sources"}, "--out", args))
    return *exit;
  const std::string out = args.text["--out"];
  const std::string sources =
      args.text.count("--sources") ? args.text["--sources"] : surgical_sim::tools::packageDir();
  const std::vector<std::string> files = shippedMeshes(sources);
  if (files.empty()) return usage("no mesh files under " + sources);
  const std::string mutants = out + "/mutants";
  fs::create_directories(mutants);
  std::ofstream csv(out + "/mesh_fuzz.csv");
  if (!csv) return usage("cannot write " + out + "/mesh_fuzz.csv");
  csv << "index,source,mutation,outcome,message\n";

  std::map<std::string, int> counts;
  for (const char* o : {"loaded", "rejected_with_message", "warned_repair", "crash", "hang"})
    counts[o] = 0;
  for (int i = 0; i < static_cast<int>(args.count); ++i) {
    const bench::MeshFuzzRow row =
        bench::writeMeshMutant(files, i, static_cast<unsigned>(args.seed), mutants);
    const bench::ChildResult child = bench::runInChild(
        [&] {
          const bench::MeshLoadResult r = bench::loadMeshForFuzz(row.file);
          return std::string(bench::toString(r.outcome)) + "\t" + r.message;
        },
        kTimeoutSeconds, kMemoryLimit);
    const std::vector<std::string> fields = bench::trialFields(child, kTimeoutSeconds, 2);
    const std::string& outcome = fields[0];
    ++counts[outcome];
    csv << i << "," << bench::csvField(fs::relative(row.source, sources).string()) << ","
        << bench::csvField(row.mutation) << "," << outcome << "," << bench::csvField(fields[1])
        << "\n";
  }
  std::cout << "mesh_fuzz: seed " << args.seed << ", " << args.count << " mutants of "
            << files.size() << " files\n";
  for (const auto& [outcome, n] : counts) std::printf("  %-22s %6d\n", outcome.c_str(), n);
  std::cout << "CSV: " << out << "/mesh_fuzz.csv\n";
  return counts["crash"] + counts["hang"] > 0 ? 1 : 0;
}
