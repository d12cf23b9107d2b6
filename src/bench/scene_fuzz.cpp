#include "surgical_sim/bench/scene_fuzz.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "surgical_sim/bench/text_mutation.h"
#include "surgical_sim/bench/tissue_case.h"
#include "surgical_sim/core/common/named_enum.h"
#include "surgical_sim/core/scene/multi_body_simulation.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace surgical_sim::bench {
namespace {

constexpr std::array<const char*, 16> kHostileNumbers{
    "1e308", "-1e308", "1e20",  "-5",     "0",
    ".nan",  ".inf",   "-.inf", "2.5",    "99999999999999999999",
    "4096",  "4097",   "-0",    "1e-320", "0x10",
    "1e999"};
constexpr std::array<const char*, 7> kWrongTypes{"[1, 2, 3]", "{a: 1}", "just text", "''",
                                                 "~",         "true",   "[[[1]]]"};

/// Position of the ':' ending the key of a "key: value" or "- key: value" line, or npos.
std::size_t keyColon(const std::string& line) {
  std::size_t i = line.find_first_not_of(' ');
  if (i == std::string::npos || line[i] == '#') return std::string::npos;
  if (line.compare(i, 2, "- ") == 0) i += 2;
  if (i >= line.size() || !(std::isalpha(static_cast<unsigned char>(line[i])) || line[i] == '_'))
    return std::string::npos;
  while (i < line.size() && (std::isalnum(static_cast<unsigned char>(line[i])) || line[i] == '_'))
    ++i;
  return i < line.size() && line[i] == ':' ? i : std::string::npos;
}

/// Column where the key of a key line starts (after indentation and "- ").
std::size_t keyStart(const std::string& line) {
  std::size_t i = line.find_first_not_of(' ');
  return line.compare(i, 2, "- ") == 0 ? i + 2 : i;
}

std::vector<std::size_t> keyLines(const std::vector<std::string>& lines) {
  std::vector<std::size_t> found;
  for (std::size_t l = 0; l < lines.size(); ++l)
    if (keyColon(lines[l]) != std::string::npos) found.push_back(l);
  return found;
}

/// (line, begin, length) of every number outside comments, delimited by YAML punctuation.
struct Span {
  std::size_t line, begin, length;
};
std::vector<Span> numberSpans(const std::vector<std::string>& lines) {
  std::vector<Span> spans;
  const auto delimiter = [](char c) {
    return c == ' ' || c == '[' || c == ']' || c == ',' || c == '{' || c == '}' || c == ':';
  };
  for (std::size_t l = 0; l < lines.size(); ++l) {
    const std::string& s = lines[l];
    const std::size_t end = std::min(s.find('#'), s.size());
    for (std::size_t i = 0; i < end;) {
      if (i > 0 && !delimiter(s[i - 1])) {
        ++i;
        continue;
      }
      std::size_t j = i;
      while (j < end && !delimiter(s[j])) ++j;
      const std::string token = s.substr(i, j - i);
      char* parsed_end = nullptr;
      std::strtod(token.c_str(), &parsed_end);
      if (!token.empty() && *parsed_end == '\0' &&
          token.find_first_of("0123456789") != std::string::npos)
        spans.push_back({l, i, j - i});
      i = j + 1;
    }
  }
  return spans;
}

/// Replaces the value of key line `l` (everything after "key:") with `value`.
std::string withValue(std::vector<std::string> lines, std::size_t l, const std::string& value) {
  lines[l] = lines[l].substr(0, keyColon(lines[l]) + 1) + " " + value;
  return joinLines(lines);
}

}  // namespace

const char* toString(SceneFuzzOutcome outcome) {
  static constexpr std::array<EnumName<SceneFuzzOutcome>, 5> kNames{{
      {SceneFuzzOutcome::Accepted, "accepted"},
      {SceneFuzzOutcome::RejectedNamingKey, "rejected_naming_key"},
      {SceneFuzzOutcome::RejectedWithoutKey, "rejected_without_key"},
      {SceneFuzzOutcome::Crash, "crash"},
      {SceneFuzzOutcome::Hang, "hang"},
  }};
  return enumName(kNames, outcome);
}

SceneMutant mutateScene(const std::string& text, std::mt19937& rng) {
  std::vector<std::string> lines = splitLines(text);
  const std::vector<std::size_t> keys = keyLines(lines);
  if (keys.empty()) return {"bit_flip", flipBits(text, rng)};
  const std::size_t k = keys[randomIndex(rng, keys.size())];
  switch (randomIndex(rng, 12)) {
    case 0:
      lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(k));
      return {"delete_key", joinLines(lines)};
    case 1: {
      // A copy of the key line only (block children stay with the second copy).
      std::string copy = lines[k];
      const std::size_t start = keyStart(copy);
      if (copy.compare(start - std::min<std::size_t>(start, 2), 2, "- ") == 0)
        copy[start - 2] = ' ';  // same map, not a new list item
      lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(k) + 1, copy);
      return {"duplicate_key", joinLines(lines)};
    }
    case 2:
      lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(k) + 1,
                   std::string(keyStart(lines[k]), ' ') + "fuzz_unknown_key: 1");
      return {"unknown_key", joinLines(lines)};
    case 3:
      return {"wrong_type", withValue(lines, k, kWrongTypes[randomIndex(rng, kWrongTypes.size())])};
    case 4:
    case 5:
    case 6: {
      const std::vector<Span> spans = numberSpans(lines);
      if (spans.empty()) return {"bit_flip", flipBits(text, rng)};
      const Span& s = spans[randomIndex(rng, spans.size())];
      const std::string value = kHostileNumbers[randomIndex(rng, kHostileNumbers.size())];
      lines[s.line].replace(s.begin, s.length, value);
      return {"number:" + value, joinLines(lines)};
    }
    case 7: {
      std::string list = "[0.1";
      const std::size_t entries = 10001 + randomIndex(rng, 40000);
      for (std::size_t i = 1; i < entries; ++i) list += ", 0.1";
      return {"giant_list", withValue(lines, k, list + "]")};
    }
    case 8: {
      for (std::size_t l : keys)
        if (lines[l].find("resolutions:") != std::string::npos) {
          const int n = std::array<int, 4>{200, 1000, 2048, 4096}[randomIndex(rng, 4)];
          const std::string r = std::to_string(n);
          return {"huge_resolution", withValue(lines, l, "[[" + r + ", " + r + ", " + r + "]]")};
        }
      return {"bit_flip", flipBits(text, rng)};
    }
    case 9: {
      if (randomIndex(rng, 2) == 0) {  // billion laughs: 10^9 values through aliases
        std::string bomb = "fuzz_bomb_0: &b0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n";
        for (int level = 1; level < 9; ++level) {
          const std::string prev = "*b" + std::to_string(level - 1);
          bomb += "fuzz_bomb_" + std::to_string(level) + ": &b" + std::to_string(level) + " [";
          for (int i = 0; i < 10; ++i) bomb += (i ? ", " : "") + prev;
          bomb += "]\n";
        }
        return {"alias_bomb", text + bomb};
      }
      return {"deep_nesting", withValue(lines, k, std::string(5000, '[') + std::string(5000, ']'))};
    }
    case 10:
      return {"bit_flip", flipBits(text, rng)};
    default:
      return {"truncate", text.substr(0, randomIndex(rng, text.size() + 1))};
  }
}

SceneKind sceneKindOf(const std::string& text, const std::string& path) {
  try {
    parseRuntimeScene(text, path);
    return SceneKind::Runtime;
  } catch (const std::exception&) {
    return SceneKind::Benchmark;
  }
}

SceneTrialResult trySceneMutant(const std::string& text, const std::string& path, SceneKind kind,
                                double construct_budget_bytes) {
  SceneTrialResult result;
  const auto rejected = [&](const std::string& message) {
    result.message = message;
    if (message.empty()) {
      result.outcome = SceneFuzzOutcome::Crash;
    } else if (message.find("key '") != std::string::npos) {
      result.outcome = SceneFuzzOutcome::RejectedNamingKey;
    } else {
      result.outcome = SceneFuzzOutcome::RejectedWithoutKey;
    }
    return result;
  };
  try {
    const RuntimeScene scene = kind == SceneKind::Runtime ? parseRuntimeScene(text, path) : [&] {
      const BenchmarkScene sweep = parseBenchmarkScene(text, path);
      return caseScene(sweep, expandSweep(sweep).front());
    }();
    if (scene.bodies.empty()) {
      if (estimateMeshSize(scene.mesh, scene.resolution, scene.element_type).bytes <=
          construct_budget_bytes) {
        TissueSimulation simulation(scene);
        result.constructed = true;
      }
    } else {
      double bytes = 0.0;  // the organs' and tet-mesh layers' meshes
      for (const BodySpec& body : scene.bodies)
        bytes += estimateMeshSize(body.mesh, body.resolution, ElementType::Tet4).bytes;
      for (const ConnectiveSpec& layer : scene.connective)
        if (layer.sampling == "tet_mesh")
          bytes += estimateMeshSize(layer.mesh, layer.resolution, ElementType::Tet4).bytes;
      if (bytes <= construct_budget_bytes) {
        MultiBodySimulation simulation(scene);
        result.constructed = true;
      }
    }
    result.outcome = SceneFuzzOutcome::Accepted;
    return result;
  } catch (const std::invalid_argument& e) {
    return rejected(e.what());
  } catch (const std::runtime_error& e) {
    return rejected(e.what());
  } catch (const std::exception& e) {
    result.message = std::string("unexpected exception: ") + e.what();
    return result;
  }
}

}  // namespace surgical_sim::bench
