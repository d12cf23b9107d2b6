#include "surgical_sim/core/robot/compliance_cache.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace surgical_sim::core {

ComplianceCache::ComplianceCache(std::string directory) : directory_(std::move(directory)) {}

std::string ComplianceCache::defaultDirectory() {
  if (const char* ros_home = std::getenv("ROS_HOME"); ros_home && *ros_home)
    return std::string(ros_home) + "/surgical_sim/compliance";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::string(home) + "/.cache/surgical_sim/compliance";
  return "";
}

std::string ComplianceCache::pathOf(const std::string& key) const {
  if (directory_.empty()) return "";
  std::uint64_t h = 14695981039346656037ull;
  for (const unsigned char c : key) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char name[40];
  std::snprintf(name, sizeof(name), "section_%016llx.txt", static_cast<unsigned long long>(h));
  return directory_ + "/" + name;
}

bool ComplianceCache::load(const std::string& key, Eigen::Matrix<double, 6, 6>& C) const {
  const std::string path = pathOf(key);
  if (path.empty()) return false;
  std::ifstream in(path);
  if (!in) return false;
  std::string stored_key;
  if (!std::getline(in, stored_key) || stored_key != key) return false;
  Eigen::Matrix<double, 6, 6> values;
  for (int i = 0; i < 36; ++i)
    if (!(in >> values.data()[i])) return false;
  C = values;
  return true;
}

bool ComplianceCache::store(const std::string& key, const Eigen::Matrix<double, 6, 6>& C) const {
  const std::string path = pathOf(key);
  if (path.empty()) return false;
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) return false;
    out << key << "\n";
    char buf[40];
    for (int i = 0; i < 36; ++i) {
      std::snprintf(buf, sizeof(buf), "%.17g", C.data()[i]);
      out << buf << ((i % 6 == 5) ? "\n" : " ");
    }
    if (!out) return false;
  }
  std::filesystem::rename(tmp, path, ec);
  return !ec;
}

}  // namespace surgical_sim::core
