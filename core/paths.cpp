#include "core/paths.hpp"

namespace slamprep {

std::filesystem::path sourceDir() { return SLAMPREP_SOURCE_DIR; }

std::filesystem::path resolveDataPath(const std::filesystem::path& path) {
  if (path.is_absolute() || std::filesystem::exists(path)) return path;
  const auto in_source = sourceDir() / path;
  return std::filesystem::exists(in_source) ? in_source : path;
}

}  // namespace slamprep
