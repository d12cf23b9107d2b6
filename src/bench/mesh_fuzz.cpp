#include "surgical_sim/bench/mesh_fuzz.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "surgical_sim/bench/text_mutation.h"
#include "surgical_sim/core/common/named_enum.h"
#include "surgical_sim/core/mesh/gmsh_reader.h"
#include "surgical_sim/core/mesh/length_unit.h"
#include "surgical_sim/core/mesh/mesh_check.h"
#include "surgical_sim/core/mesh/surface_reader.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

namespace {

/// Values a numeric token is replaced with: non-finite, overflowing, huge, negative, zero,
/// non-integer, hexadecimal, empty (token removed).
constexpr std::array<const char*, 14> kHostileNumbers{
    "nan",        "inf", "-inf",   "1e309", "1e300",     "-1", "0", "99999999999999999999",
    "2147483648", "1.5", "-99999", "0x10",  "100000001", ""};

bool isNumber(const std::string& token) {
  char* end = nullptr;
  std::strtod(token.c_str(), &end);
  return !token.empty() && *end == '\0';
}

std::vector<std::string> splitTokens(const std::string& line) {
  std::istringstream words(line);
  std::vector<std::string> tokens;
  std::string token;
  while (words >> token) tokens.push_back(token);
  return tokens;
}

std::string joinTokens(const std::vector<std::string>& tokens) {
  std::string out;
  for (const std::string& t : tokens) out += (out.empty() ? "" : " ") + t;
  return out;
}

/// Positions (line, token) of every numeric token.
std::vector<std::pair<std::size_t, std::size_t>> numericTokens(
    const std::vector<std::string>& lines) {
  std::vector<std::pair<std::size_t, std::size_t>> found;
  for (std::size_t l = 0; l < lines.size(); ++l) {
    const std::vector<std::string> tokens = splitTokens(lines[l]);
    for (std::size_t t = 0; t < tokens.size(); ++t)
      if (isNumber(tokens[t])) found.emplace_back(l, t);
  }
  return found;
}

MeshMutant truncateBytes(const std::string& bytes, std::mt19937& rng) {
  return {"truncate_bytes", bytes.substr(0, randomIndex(rng, bytes.size() + 1))};
}

MeshMutant mutateBinary(std::string bytes, std::mt19937& rng) {
  constexpr std::size_t kHeader = 84;  // binary STL: 80-byte header + uint32 count
  switch (randomIndex(rng, 4)) {
    case 0:
      return {"bit_flip", flipBits(bytes, rng)};
    case 1:
      return truncateBytes(bytes, rng);
    case 2:
      if (bytes.size() >= kHeader + 4) {
        const float nan = std::numeric_limits<float>::quiet_NaN();
        std::memcpy(&bytes[kHeader + 4 * randomIndex(rng, (bytes.size() - kHeader) / 4)], &nan, 4);
      }
      return {"binary_nan", bytes};
    default: {
      const std::uint32_t count =
          randomIndex(rng, 2) ? 0xFFFFFFFFu : static_cast<std::uint32_t>(rng());
      if (bytes.size() >= kHeader)
        for (int k = 0; k < 4; ++k) bytes[80 + k] = static_cast<char>((count >> (8 * k)) & 0xFF);
      return {"binary_count", bytes};
    }
  }
}

MeshMutant mutateText(const std::string& bytes, std::mt19937& rng) {
  std::vector<std::string> lines = splitLines(bytes);
  if (lines.empty()) return {"bit_flip", flipBits(bytes, rng)};
  const std::size_t line = randomIndex(rng, lines.size());
  switch (randomIndex(rng, 10)) {
    case 0:
    case 1: {  // the most frequent: a count, tag, coordinate or node reference goes bad
      const auto numbers = numericTokens(lines);
      if (numbers.empty()) return {"bit_flip", flipBits(bytes, rng)};
      const auto [l, t] = numbers[randomIndex(rng, numbers.size())];
      std::vector<std::string> tokens = splitTokens(lines[l]);
      const std::string value = kHostileNumbers[randomIndex(rng, kHostileNumbers.size())];
      if (value.empty()) {
        tokens.erase(tokens.begin() + static_cast<std::ptrdiff_t>(t));
      } else {
        tokens[t] = value;
      }
      lines[l] = joinTokens(tokens);
      return {"number:" + (value.empty() ? std::string("removed") : value), joinLines(lines)};
    }
    case 2: {  // every token with a decimal point or exponent (coordinates) scaled by 1e6
      for (std::string& l : lines) {
        std::vector<std::string> tokens = splitTokens(l);
        for (std::string& t : tokens)
          if (isNumber(t) && t.find_first_of(".eE") != std::string::npos)
            t = std::to_string(std::strtod(t.c_str(), nullptr) * 1e6);
        l = joinTokens(tokens);
      }
      return {"scale_1e6", joinLines(lines)};
    }
    case 3:
      lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(line));
      return {"delete_line", joinLines(lines)};
    case 4:
      lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(line), lines[line]);
      return {"duplicate_line", joinLines(lines)};
    case 5:
      std::swap(lines[line], lines[randomIndex(rng, lines.size())]);
      return {"swap_lines", joinLines(lines)};
    case 6: {  // a section header ($Nodes, solid, ...) with one letter changed
      std::vector<std::size_t> headers;
      for (std::size_t l = 0; l < lines.size(); ++l)
        if (!lines[l].empty() &&
            (lines[l][0] == '$' || std::isalpha(static_cast<unsigned char>(lines[l][0]))))
          headers.push_back(l);
      if (headers.empty()) return {"bit_flip", flipBits(bytes, rng)};
      std::string& h = lines[headers[randomIndex(rng, headers.size())]];
      if (h.size() < 2) h += 'm';
      char& c = h[1 + randomIndex(rng, h.size() - 1)];
      c = c == 'm' ? 'n' : 'm';
      return {"rename_section", joinLines(lines)};
    }
    case 7: {  // cut right before a section boundary or after a random line
      std::vector<std::size_t> headers;
      for (std::size_t l = 0; l < lines.size(); ++l)
        if (!lines[l].empty() && lines[l][0] == '$') headers.push_back(l);
      const std::size_t end = headers.empty() ? line : headers[randomIndex(rng, headers.size())];
      return {"truncate_line", joinLines(lines, end)};
    }
    case 8:
      return truncateBytes(bytes, rng);
    default:
      return {"bit_flip", flipBits(bytes, rng)};
  }
}

bool namesFile(const std::string& message, const std::string& path) {
  return !message.empty() && message.find(path) != std::string::npos;
}

/// Classifies a load that threw: a standard error naming the file is a rejection.
MeshLoadResult rejected(const std::string& path, const std::string& message) {
  if (namesFile(message, path)) return {MeshLoadOutcome::RejectedWithMessage, message};
  return {MeshLoadOutcome::Crash, "message does not name the file: '" + message + "'"};
}

MeshLoadResult loadVolume(const std::string& path) {
  const TetMesh mesh = readGmsh(path, lengthUnitToMetres("mm"));
  try {
    requireValidMesh(mesh);
  } catch (const std::invalid_argument& e) {
    return rejected(path, path + ": " + e.what());
  }
  // Every DOF fixed: only the scale warning can fire.
  std::vector<int> all_dofs(static_cast<std::size_t>(3 * mesh.numNodes()));
  for (std::size_t i = 0; i < all_dofs.size(); ++i) all_dofs[i] = static_cast<int>(i);
  const std::vector<std::string> warnings = meshWarnings(mesh, all_dofs);
  if (warnings.empty()) return {MeshLoadOutcome::Loaded, ""};
  return {MeshLoadOutcome::WarnedRepair, path + ": " + warnings.front()};
}

MeshLoadResult loadSurface(const std::string& path, bool obj) {
  const TriMesh mesh = obj ? readObj(path, 1e-3) : readStl(path, 1e-3);
  const auto n = mesh.vertices.cols();
  if (!mesh.vertices.allFinite())
    return {MeshLoadOutcome::Crash, "loaded surface has a non-finite vertex"};
  if (mesh.triangles.size() > 0 &&
      (mesh.triangles.minCoeff() < 0 || mesh.triangles.maxCoeff() >= n))
    return {MeshLoadOutcome::Crash, "loaded surface has a vertex index out of range"};
  return {MeshLoadOutcome::Loaded, ""};
}

}  // namespace

const char* toString(MeshLoadOutcome outcome) {
  static constexpr std::array<EnumName<MeshLoadOutcome>, 4> kNames{{
      {MeshLoadOutcome::Loaded, "loaded"},
      {MeshLoadOutcome::RejectedWithMessage, "rejected_with_message"},
      {MeshLoadOutcome::WarnedRepair, "warned_repair"},
      {MeshLoadOutcome::Crash, "crash"},
  }};
  return enumName(kNames, outcome);
}

MeshLoadResult loadMeshForFuzz(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  try {
    if (extension == ".msh") return loadVolume(path);
    if (extension == ".obj" || extension == ".stl") return loadSurface(path, extension == ".obj");
    return {MeshLoadOutcome::Crash, "unknown mesh extension '" + extension + "'"};
  } catch (const std::runtime_error& e) {
    return rejected(path, e.what());
  } catch (const std::invalid_argument& e) {
    return rejected(path, e.what());
  } catch (const std::exception& e) {
    return {MeshLoadOutcome::Crash, std::string("unexpected exception: ") + e.what()};
  }
}

MeshMutant mutateMeshFile(const std::string& bytes, std::mt19937& rng) {
  if (bytes.find('\0') != std::string::npos) return mutateBinary(bytes, rng);
  return mutateText(bytes, rng);
}

MeshFuzzRow writeMeshMutant(const std::vector<std::string>& sources, int index, unsigned seed,
                            const std::string& dir) {
  if (sources.empty()) throw std::invalid_argument("writeMeshMutant: no source files");
  if (index < 0)
    throw std::invalid_argument("writeMeshMutant: index = " + std::to_string(index) +
                                " must be >= 0");
  MeshFuzzRow row;
  row.source = sources[static_cast<std::size_t>(index) % sources.size()];
  std::ifstream in(row.source, std::ios::binary);
  if (!in) throw std::runtime_error(row.source + ": cannot open file");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::mt19937 rng(seed + static_cast<unsigned>(index));
  MeshMutant mutant = mutateMeshFile(bytes, rng);
  row.mutation = mutant.mutation;
  row.file = dir + "/mutant_" + std::to_string(index) +
             std::filesystem::path(row.source).extension().string();
  std::ofstream out(row.file, std::ios::binary);
  out << mutant.bytes;
  if (!out) throw std::runtime_error(row.file + ": cannot write file");
  return row;
}

}  // namespace surgical_sim::bench
