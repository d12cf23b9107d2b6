#include "surgical_sim/core/common/text_file.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace surgical_sim::core {

std::string readTextFile(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  if (!in || !(text << in.rdbuf())) throw std::invalid_argument("cannot read '" + path + "'");
  return text.str();
}

}  // namespace surgical_sim::core
