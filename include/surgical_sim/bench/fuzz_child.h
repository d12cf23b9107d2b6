#pragma once
// The command line of a fuzz tool, and one fuzz trial in a forked child process (shared by
// mesh_fuzz and scene_fuzz): a crash (signal), a hang (wall-time limit) or an allocation beyond
// the address-space limit cannot take the campaign down, and is reported as such.

#include <sys/resource.h>

#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace surgical_sim::bench {

/// How a child trial ended.
struct ChildResult {
  enum class End { Finished, Signalled, TimedOut, ForkFailed };
  End end = End::ForkFailed;
  std::string output;  ///< what the trial returned (Finished only)
  int signal = 0;      ///< terminating signal (Signalled only)
  double seconds = 0.0;
};

/// Runs `trial` in a child with at most `timeout_s` [s] of wall time and `memory_limit` [bytes]
/// of address space; the child sends the trial's return value back through a pipe. An exception
/// escaping `trial` is returned as "uncaught exception: <what>".
ChildResult runInChild(const std::function<std::string()>& trial, double timeout_s,
                       rlim_t memory_limit);

/// The `count` >= 2 tab-separated fields of a trial's output: an outcome name first, a message
/// last (the rest of the output, tabs included). A child that ran out of time (`timeout_s` [s])
/// gives {"hang", "", ..., "no result after <timeout_s> s"}; one killed by a signal, never forked,
/// or whose output has fewer fields gives {"crash", "", ..., why}.
std::vector<std::string> trialFields(const ChildResult& child, double timeout_s, std::size_t count);

/// `text` as one CSV field: quoted, inner quotes doubled, bytes outside printable ASCII (line
/// breaks, bytes of corrupted files) written as \xNN.
std::string csvField(const std::string& text);

/// Command line of a fuzz campaign tool: --help / -h, --seed S, --count N and string options.
struct FuzzArgs {
  bool help = false;
  long long seed = -1;
  long long count = 0;
  std::map<std::string, std::string> text;  ///< the string options given, by name ("--csv")
};

/// Parses "--name value" pairs into `out`: seed in [0, 2^32), count in [min_count, 1e6], string
/// options from `text_options`, of which `required` must be given. Returns "" or what is wrong
/// (missing value or option, unknown option, bad number, out of range); stops at --help.
std::string parseFuzzArgs(int argc, char** argv, long long min_count,
                          const std::set<std::string>& text_options, const std::string& required,
                          FuzzArgs& out);

/// Parses a fuzz tool's command line with parseFuzzArgs() and answers what ends the tool there:
/// --help prints `usage` on stdout (exit code 0); a bad command line prints "<tool>: <problem>"
/// and `usage` on stderr (exit code 2). nullopt: the campaign runs with `out`.
std::optional<int> fuzzCommandLineExit(const std::string& tool, const std::string& usage, int argc,
                                       char** argv, long long min_count,
                                       const std::set<std::string>& text_options,
                                       const std::string& required, FuzzArgs& out);

}  // namespace surgical_sim::bench
