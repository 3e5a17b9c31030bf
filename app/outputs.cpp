#include "app/outputs.hpp"

#include <algorithm>
#include <fstream>

#include "core/error.hpp"

namespace slamprep::app {
namespace {

namespace fs = std::filesystem;

std::string quoted(const std::string& option, const fs::path& path) {
  return option + " " + path.string();
}

bool present(const fs::path& path) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(path, ec));
}

// Absolute, symlinks resolved, no trailing slash: "ds/" and "./ds" name the same directory.
fs::path resolved(const fs::path& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec).lexically_normal();
  return p.has_filename() ? p : p.parent_path();
}

}  // namespace

void checkOutputFile(const fs::path& file, const std::string& option, bool force) {
  std::error_code ec;
  if (fs::is_directory(file, ec))
    throw InputError(quoted(option, file), "is a directory; give a file name");
  if (present(file) && !force)
    throw InputError(quoted(option, file), "exists; give --force to replace it");
}

void checkOutputDirectory(const fs::path& dir, const std::string& option, bool force,
                          const eval::ReplaceableDirectory& replaceable, const std::string& kind) {
  if (!present(dir)) return;
  std::error_code ec;
  if (!fs::is_directory(dir, ec) || !replaceable(dir))
    throw InputError(quoted(option, dir),
                     "exists and is not " + kind + "; refusing to replace it, even with --force");
  if (!force) throw InputError(quoted(option, dir), "exists; give --force to replace it");
}

void checkOutputDataset(const fs::path& dir, const std::string& option, bool force) {
  checkOutputDirectory(dir, option, force, eval::isReplaceableDataset,
                       "a dataset directory (no dataset.json)");
}

void checkInputDataset(const fs::path& dir, const std::string& option) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(quoted(option, dir), "not a dataset directory (missing or not a directory)");
  if (!fs::exists(dir / eval::kDatasetJson, ec))
    throw InputError(quoted(option, dir), "not a dataset directory (no dataset.json)");
}

void checkInputFile(const fs::path& file, const std::string& option) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) throw InputError(quoted(option, file), "is a directory");
  if (!std::ifstream(file)) throw InputError(quoted(option, file), "cannot open file");
}

void checkNotInside(const fs::path& out, const fs::path& input, const std::string& option) {
  const fs::path o = resolved(out), i = resolved(input);
  if (std::mismatch(i.begin(), i.end(), o.begin(), o.end()).first == i.end())
    throw InputError(quoted(option, out), "is inside the input " + input.string() +
                                              "; a command never writes into "
                                              "its input: choose another --out");
}

}  // namespace slamprep::app
