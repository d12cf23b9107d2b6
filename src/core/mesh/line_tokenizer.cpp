#include "surgical_sim/core/mesh/line_tokenizer.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace surgical_sim::core {

LineTokenizer::LineTokenizer(const std::string& path) : path_(path), in_(path) {
  if (!in_) throw std::runtime_error(path + ": cannot open file");
  in_.seekg(0, std::ios::end);
  size_ = static_cast<long long>(in_.tellg());
  in_.seekg(0, std::ios::beg);
  if (!in_ || size_ < 0) throw std::runtime_error(path + ": cannot read file size");
}

long long LineTokenizer::bytesRemaining() {
  const std::streampos position = in_.tellg();
  return position < 0 ? 0 : size_ - static_cast<long long>(position);
}

bool LineTokenizer::next() {
  tokens_.clear();
  std::string line;
  while (std::getline(in_, line)) {
    ++line_number_;
    std::istringstream words(line);
    std::string token;
    while (words >> token) tokens_.push_back(token);
    if (!tokens_.empty()) return true;
  }
  return false;
}

void LineTokenizer::fail(const std::string& what) const {
  throw std::runtime_error(path_ + ":" + std::to_string(line_number_) + ": " + what);
}

long long LineTokenizer::toInteger(const std::string& token, const std::string& what) const {
  errno = 0;
  char* end = nullptr;
  const long long value = std::strtoll(token.c_str(), &end, 10);
  if (token.empty() || *end != '\0' || errno == ERANGE) {
    fail("bad number '" + token + "' for " + what);
  }
  return value;
}

double LineTokenizer::toDouble(const std::string& token, const std::string& what) const {
  char* end = nullptr;
  const double value = std::strtod(token.c_str(), &end);  // underflow to 0 is accepted
  if (token.empty() || *end != '\0' || !std::isfinite(value)) {
    fail("bad number '" + token + "' for " + what);
  }
  return value;
}

void LineTokenizer::requireTokens(std::size_t count, const std::string& what) const {
  if (tokens_.size() < count) {
    fail("expected at least " + std::to_string(count) + " values for " + what + ", got " +
         std::to_string(tokens_.size()));
  }
}

}  // namespace surgical_sim::core
