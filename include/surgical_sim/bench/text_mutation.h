#pragma once
// Building blocks of the file mutators of the mesh and scene fuzzers.

#include <cstddef>
#include <random>
#include <string>
#include <vector>

namespace surgical_sim::bench {

/// A uniformly drawn index in [0, n), n >= 1.
std::size_t randomIndex(std::mt19937& rng, std::size_t n);

/// The lines of `text`, without their line breaks.
std::vector<std::string> splitLines(const std::string& text);

/// The first `end` of `lines` (all of them by default), each followed by a line break.
std::string joinLines(const std::vector<std::string>& lines, std::size_t end = std::string::npos);

/// `bytes` with 1 to 3 randomly chosen bits flipped (unchanged when empty).
std::string flipBits(std::string bytes, std::mt19937& rng);

}  // namespace surgical_sim::bench
