#include "slamprep/core/paths.hpp"

#include <algorithm>
#include <cstdlib>
#include <system_error>

namespace slamprep {
namespace fs = std::filesystem;

namespace {

// The running executable's folder; empty where /proc is not mounted.
fs::path executableDir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

bool isDirectory(const fs::path& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

}  // namespace

fs::path dataDir() {
  if (const char* env = std::getenv("SLAMPREP_DATA_DIR"); env && *env) return env;
  const fs::path exe_dir = executableDir();
  if (exe_dir.empty()) return {};
  for (const fs::path& candidate : {exe_dir / ".." / "share" / "slamprep",  // installed
                                    exe_dir / "share" / "slamprep"})        // build tree
    if (isDirectory(candidate)) return candidate.lexically_normal();
  return {};
}

fs::path resolveDataPath(const fs::path& path) {
  if (path.is_absolute() || fs::exists(path)) return path;
  const fs::path data_dir = dataDir();
  if (data_dir.empty()) return path;
  const fs::path in_data = data_dir / path;
  return fs::exists(in_data) ? in_data : path;
}

fs::path resolvedPath(const fs::path& path) {
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec);
  fs::path p = fs::weakly_canonical(absolute, ec);
  if (ec) p = absolute;
  p = p.lexically_normal();
  return p.has_filename() || p == p.root_path() ? p : p.parent_path();
}

bool isSameOrInside(const fs::path& inner, const fs::path& outer) {
  const fs::path i = resolvedPath(inner), o = resolvedPath(outer);
  return std::mismatch(o.begin(), o.end(), i.begin(), i.end()).first == o.end();
}

}  // namespace slamprep
