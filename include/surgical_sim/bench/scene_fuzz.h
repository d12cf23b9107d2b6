#pragma once

#include <random>
#include <string>

namespace surgical_sim::bench {

/// What happened to a (possibly corrupted) scene file.
enum class SceneFuzzOutcome {
  Accepted,            ///< parsed (and constructed, if small enough)
  RejectedNamingKey,   ///< std::invalid_argument / std::runtime_error containing "key '"
  RejectedWithoutKey,  ///< a rejection whose message names no key (e.g. YAML syntax errors)
  Crash,               ///< any other exception type or an empty message
  Hang,                ///< no result within the time limit (assigned by a caller that runs
                       ///< trials in a child process; trySceneMutant() never returns it)
};

/// "accepted", "rejected_naming_key", "rejected_without_key", "crash", "hang".
const char* toString(SceneFuzzOutcome outcome);

/// A corrupted copy of a scene file and the name of the corruption, e.g. "duplicate_key".
struct SceneMutant {
  std::string mutation;
  std::string text;
};

/// Derives one corrupted copy of the YAML text of a scene: a key line deleted, duplicated or
/// followed by an unknown key; a value replaced by one of the wrong type; a number replaced by a
/// hostile one (huge, negative, zero, NaN, Inf, non-integer, overflowing, hex); a value replaced
/// by a giant list (above the list-length limit) or a huge mesh resolution; an alias bomb or
/// deeply nested lists appended; 1-3 flipped bits; a truncation.
SceneMutant mutateScene(const std::string& text, std::mt19937& rng);

/// Outcome of trySceneMutant().
struct SceneTrialResult {
  SceneFuzzOutcome outcome = SceneFuzzOutcome::Crash;
  std::string message;       ///< the rejection, or "" when accepted
  bool constructed = false;  ///< a TissueSimulation was built
};

/// The two kinds of scene file.
enum class SceneKind { Runtime, Benchmark };

/// Runtime if `text` parses as a runtime scene, else Benchmark (the kind of a seed file).
SceneKind sceneKindOf(const std::string& text, const std::string& path);

/// Parses `text` as a scene of `kind` (parseRuntimeScene / parseBenchmarkScene) and, when it
/// parses and the estimate of its mesh (a benchmark: its first case; estimateMeshSize()) is at
/// most construct_budget_bytes [bytes], constructs a TissueSimulation from it (a benchmark: from
/// its first case). Never throws.
SceneTrialResult trySceneMutant(const std::string& text, const std::string& path, SceneKind kind,
                                double construct_budget_bytes);

}  // namespace surgical_sim::bench
