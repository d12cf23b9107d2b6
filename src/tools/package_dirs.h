#pragma once
// Where a tool finds the package's files (header only, shared by the executables in src/tools):
// run from the build (its directory is SURGICAL_SIM_BUILD_BIN_DIR), the source tree; installed,
// the Python scripts beside the executable and config/ in the package's share folder
// (SURGICAL_SIM_INSTALL_SHARE_FROM_BIN, relative to the executable).

#include <filesystem>
#include <string>
#include <system_error>

namespace surgical_sim::tools {

/// Directory of the running executable ("" if /proc/self/exe cannot be read).
inline std::filesystem::path executableDir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : exe.parent_path();
}

/// True when the running executable is the one of the build (devel) space.
inline bool runFromBuild() {
  std::error_code ec;
  return std::filesystem::equivalent(executableDir(), SURGICAL_SIM_BUILD_BIN_DIR, ec) && !ec;
}

/// The package's root: the source tree from the build, the share folder when installed (holds
/// config/ and, installed, the bags of test/data/ the launch files use).
inline std::string packageDir() {
  return runFromBuild()
             ? std::string(SURGICAL_SIM_SOURCE_DIR)
             : (executableDir() / SURGICAL_SIM_INSTALL_SHARE_FROM_BIN).lexically_normal().string();
}

/// The package's config/ directory (scenes, robot descriptions, meshes).
inline std::string configDir() { return packageDir() + "/config"; }

/// Directory of the package's Python scripts (plot_*.py, summarize_bench.py).
inline std::string scriptsDir() {
  return runFromBuild() ? std::string(SURGICAL_SIM_SOURCE_DIR) + "/scripts"
                        : executableDir().string();
}

}  // namespace surgical_sim::tools
