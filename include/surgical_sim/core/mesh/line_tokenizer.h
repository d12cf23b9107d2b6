#pragma once

#include <fstream>
#include <string>
#include <vector>

namespace surgical_sim::core {

/// Reads a text file one non-blank line at a time, splits each line into whitespace-separated
/// tokens and reports parse errors as std::runtime_error "path:line: what". Shared by the
/// text mesh readers (Gmsh, OBJ, ASCII STL).
class LineTokenizer {
 public:
  /// Opens the file.
  /// @throws std::runtime_error "path: cannot open file" if it cannot be read.
  explicit LineTokenizer(const std::string& path);

  /// Advances to the next line holding at least one token.
  /// @return false at end of file (tokens() is then empty).
  bool next();

  /// Tokens of the current line.
  const std::vector<std::string>& tokens() const { return tokens_; }
  /// 1-based number of the current line (after the end of file: the number of lines read).
  int lineNumber() const { return line_number_; }
  /// Path of the file, as given to the constructor.
  const std::string& path() const { return path_; }
  /// Bytes of the file after the current line [bytes] (0 at end of file).
  long long bytesRemaining();

  /// Throws std::runtime_error "path:line: what" for the current line.
  [[noreturn]] void fail(const std::string& what) const;

  /// Parses a whole token as a base-10 integer.
  /// @param what describes the value in the error message, e.g. "node tag".
  /// @throws std::runtime_error "path:line: bad number 'token' for <what>".
  long long toInteger(const std::string& token, const std::string& what) const;
  /// Parses a whole token as a finite floating-point number.
  /// @throws std::runtime_error "path:line: bad number 'token' for <what>".
  double toDouble(const std::string& token, const std::string& what) const;

  /// Requires the current line to have at least `count` tokens.
  /// @throws std::runtime_error "path:line: expected at least <count> values for <what>, got n".
  void requireTokens(std::size_t count, const std::string& what) const;

 private:
  std::string path_;
  std::ifstream in_;
  long long size_ = 0;  ///< file size [bytes]
  std::vector<std::string> tokens_;
  int line_number_ = 0;
};

}  // namespace surgical_sim::core
