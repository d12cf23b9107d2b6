#pragma once
// Command-line plumbing shared by the benchmark executables in src/tools (header only: every
// .cpp there is its own executable).

#include <cstdlib>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iostream>
#include <limits>
#include <optional>
#include <string>

#include "package_dirs.h"
#include "surgical_sim/bench/fuzz_child.h"

namespace surgical_sim::tools {

/// True when the command line asks for help (--help or -h anywhere): the tool then prints its
/// usage on stdout and exits 0 without doing or writing anything.
inline bool wantsHelp(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") return true;
  }
  return false;
}

/// `text` as a count: decimal digits only, in [1, INT_MAX]; nullopt otherwise (no sign, no
/// exponent, no overflow to a wrapped value as with atoi).
inline std::optional<int> parseCount(const std::string& text) {
  if (text.empty() || text.size() > 10) return std::nullopt;
  for (const char c : text)
    if (c < '0' || c > '9') return std::nullopt;
  const long long value = std::stoll(text);
  if (value < 1 || value > std::numeric_limits<int>::max()) return std::nullopt;
  return static_cast<int>(value);
}

/// Prints "<tool>: <what>" as one line on stderr (unbuffered): a long benchmark shows one line per
/// case while it runs, also when its stdout goes to a file.
inline void progress(const std::string& tool, const std::string& what) {
  std::cerr << tool << ": " << what << std::endl;
}

/// "[i/n] " for the progress line of case i (0-based) of n.
inline std::string caseCounter(std::size_t i, std::size_t n) {
  return "[" + std::to_string(i + 1) + "/" + std::to_string(n) + "] ";
}

/// Arguments of a scene benchmark: <scene.yaml> [--csv FILE] [--plot FILE].
struct SceneBenchArgs {
  std::string scene, csv, plot;
};

/// Parses argv into args; returns an empty string, or what is wrong with the command line.
inline std::string parseSceneBenchArgs(int argc, char** argv, SceneBenchArgs& args) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--csv" || arg == "--plot") && i + 1 < argc) {
      (arg == "--csv" ? args.csv : args.plot) = argv[++i];
    } else if (!arg.empty() && arg[0] == '-') {
      return "unknown option " + arg;
    } else if (args.scene.empty()) {
      args.scene = arg;
    } else {
      return "more than one scene given";
    }
  }
  if (args.scene.empty()) return "no scene given";
  if (!args.plot.empty() && args.csv.empty()) return "--plot needs --csv";
  return "";
}

/// Opens `path` for writing into csv unless path is empty; false (with a message on stderr
/// prefixed by `tool`) if it cannot be written.
inline bool openCsv(const std::string& tool, const std::string& path, std::ofstream& csv) {
  if (path.empty()) return true;
  csv.open(path);
  if (csv) return true;
  std::cerr << tool << ": cannot write " << path << "\n";
  return false;
}

/// Runs scripts/<script> with the quoted arguments (e.g. CSV, PNG, title) through
/// /usr/bin/python3; false (with a message on stderr prefixed by `tool`) if it fails.
inline bool runPlotScript(const std::string& tool, const std::string& script,
                          std::initializer_list<std::string> arguments) {
  std::string cmd = "/usr/bin/python3 '" + scriptsDir() + "/" + script + "'";
  for (const std::string& a : arguments) cmd += " '" + a + "'";
  if (std::system(cmd.c_str()) == 0) return true;
  std::cerr << tool << ": plotting failed (" << cmd << ")\n";
  return false;
}

/// Wall time limit of one benchmark case run in a child process (runCaseInChild) [s].
inline constexpr double kCaseTimeoutSeconds = 4.0 * 3600.0;

/// Runs `work` in a child process (bench::runInChild, no memory limit, kCaseTimeoutSeconds), so
/// that the child's peak resident memory is the case's own and a crash ends only the case.
/// Returns the text `work` returned; nullopt, after "<tool>: <what> failed: <why>" on stderr,
/// when it threw, crashed or timed out.
inline std::optional<std::string> runCaseInChild(const std::string& tool, const std::string& what,
                                                 const std::function<std::string()>& work) {
  const std::string ok = "ok\n";
  const bench::ChildResult child = bench::runInChild(
      [&]() -> std::string {
        try {
          return ok + work();
        } catch (const std::exception& e) {
          return std::string("error\n") + e.what();
        }
      },
      kCaseTimeoutSeconds, RLIM_INFINITY);
  if (child.end == bench::ChildResult::End::Finished && child.output.rfind(ok, 0) == 0)
    return child.output.substr(ok.size());
  std::string why = "crashed";
  if (child.end == bench::ChildResult::End::Finished)
    why = child.output.substr(child.output.find('\n') + 1);
  else if (child.end == bench::ChildResult::End::Signalled)
    why = "killed by signal " + std::to_string(child.signal);
  else if (child.end == bench::ChildResult::End::TimedOut)
    why = "no result after " + std::to_string(kCaseTimeoutSeconds) + " s";
  std::cerr << tool << ": " << what << " failed: " << why << "\n";
  return std::nullopt;
}

}  // namespace surgical_sim::tools
