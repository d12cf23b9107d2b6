#pragma once

#include <Eigen/Core>
#include <string>

namespace surgical_sim::core {

/// On-disk cache of condensed 6x6 section compliances. An entry is the file
/// <directory>/section_<16 hex digits of FNV-1a 64 of key>.txt holding the key on its first line
/// and the 36 values (column-major, 17 significant digits) after it, so a hash collision is
/// detected and treated as a miss.
class ComplianceCache {
 public:
  /// @param directory cache directory; created on the first store(). Empty: caching disabled.
  explicit ComplianceCache(std::string directory);

  /// $ROS_HOME/surgical_sim/compliance if ROS_HOME is set, else
  /// $HOME/.cache/surgical_sim/compliance, else "" (no caching).
  static std::string defaultDirectory();

  /// Reads the entry for key into C. Returns false on a miss (absent, unreadable, other key).
  bool load(const std::string& key, Eigen::Matrix<double, 6, 6>& C) const;
  /// Writes the entry for key (best effort: returns false if the file cannot be written).
  bool store(const std::string& key, const Eigen::Matrix<double, 6, 6>& C) const;
  /// Path of the entry for key ("" if caching is disabled).
  std::string pathOf(const std::string& key) const;

 private:
  std::string directory_;
};

}  // namespace surgical_sim::core
