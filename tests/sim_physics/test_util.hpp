#pragma once
// Helpers shared by the sim/physics tests.

#include <filesystem>
#include <fstream>
#include <string>

namespace slamprep::sim::test {

inline std::filesystem::path worldFile(const std::string& name) {
  return std::filesystem::path(SLAMPREP_SOURCE_DIR) / "worlds" / name;
}

/// Writes `text` to a fresh file under the build tree and returns its path.
inline std::filesystem::path writeTemp(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::path(SLAMPREP_BINARY_DIR) / "test_tmp" / "sim_physics";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace slamprep::sim::test
