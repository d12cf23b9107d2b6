#include "surgical_sim/bench/text_mutation.h"

#include <sstream>

namespace surgical_sim::bench {

std::size_t randomIndex(std::mt19937& rng, std::size_t n) {
  return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
}

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

std::string joinLines(const std::vector<std::string>& lines, std::size_t end) {
  std::string out;
  for (std::size_t i = 0; i < end && i < lines.size(); ++i) out += lines[i] + "\n";
  return out;
}

std::string flipBits(std::string bytes, std::mt19937& rng) {
  const std::size_t flips = 1 + randomIndex(rng, 3);
  for (std::size_t i = 0; i < flips && !bytes.empty(); ++i)
    bytes[randomIndex(rng, bytes.size())] ^= static_cast<char>(1u << randomIndex(rng, 8));
  return bytes;
}

}  // namespace surgical_sim::bench
