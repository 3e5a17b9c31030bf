#include "slamprep/app/outputs.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/paths.hpp"

namespace slamprep::app {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kNameMax = 255;  // bytes in one file name on Linux filesystems

std::string quoted(const std::string& option, const fs::path& path) {
  return option + " " + path.string();
}

bool present(const fs::path& path) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(path, ec));
}

void checkName(const fs::path& path, const std::string& option) {
  if (path.empty()) throw InputError(option, "is empty: give a path");
  for (const fs::path& part : path)
    if (part.string().size() > kNameMax)
      throw InputError(quoted(option, path), "has a name longer than " + std::to_string(kNameMax) +
                                                 " bytes, which no Linux filesystem stores");
}

enum class Relation { kApart, kSame, kInside, kContains };

// Where `path` lies relative to `other`, both resolved.
Relation relation(const fs::path& path, const fs::path& other) {
  const bool inside = isSameOrInside(path, other), contains = isSameOrInside(other, path);
  if (inside && contains) return Relation::kSame;
  return inside ? Relation::kInside : contains ? Relation::kContains : Relation::kApart;
}

// The nearest existing folder above `path` must be a folder this process may write into: a run
// must not find out after an hour that its output cannot be stored.
void checkWritable(const fs::path& path, const std::string& option) {
  std::error_code ec;
  fs::path folder = resolvedPath(path).parent_path();
  while (!folder.empty() && !fs::exists(fs::symlink_status(folder, ec)) &&
         folder != folder.root_path())
    folder = folder.parent_path();
  if (!fs::is_directory(folder, ec))
    throw InputError(quoted(option, path), folder.string() + " is not a folder");
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    throw InputError(quoted(option, path),
                     "cannot write into " + folder.string() + ": " + std::strerror(errno));
}

}  // namespace

OutputGuard& OutputGuard::input(const fs::path& path, const std::string& option) {
  if (!path.empty()) inputs_.push_back({path, option});
  return *this;
}

OutputGuard& OutputGuard::file(const fs::path& path, const std::string& option) {
  outputs_.push_back({{path, option}, false, nullptr, ""});
  return *this;
}

OutputGuard& OutputGuard::dataset(const fs::path& dir, const std::string& option) {
  return directory(dir, option, eval::isReplaceableDataset,
                   "a dataset directory (no dataset.json)");
}

OutputGuard& OutputGuard::directory(const fs::path& dir, const std::string& option,
                                    eval::ReplaceableDirectory replaceable, std::string kind) {
  outputs_.push_back({{dir, option}, true, std::move(replaceable), std::move(kind)});
  return *this;
}

void OutputGuard::checkRelations(const Output& out, std::size_t index) const {
  const std::string where = quoted(out.option, out.path);
  const std::string choose = ": choose another " + out.option;
  for (const Named& in : inputs_) {
    const std::string input = "the input " + quoted(in.option, in.path);
    switch (relation(out.path, in.path)) {
      case Relation::kSame:
        throw InputError(where, "is " + input + "; a command never replaces its input, even with " +
                                    "--force" + choose);
      case Relation::kInside:
        throw InputError(where,
                         "is inside " + input + "; a command never writes into its input" + choose);
      case Relation::kContains:
        throw InputError(where,
                         "contains " + input + "; replacing it would delete that input" + choose);
      case Relation::kApart:
        break;
    }
  }
  for (std::size_t k = 0; k < index; ++k) {
    const Relation r = relation(out.path, outputs_[k].path);
    if (r == Relation::kApart) continue;
    const char* how = r == Relation::kSame     ? "is also "
                      : r == Relation::kInside ? "is inside "
                                               : "contains ";
    throw InputError(where, how + quoted(outputs_[k].option, outputs_[k].path) +
                                "; give each output its own path");
  }
}

void OutputGuard::checkExisting(const Output& out) const {
  if (!present(out.path)) return;
  const std::string where = quoted(out.option, out.path);
  std::error_code ec;
  const bool is_directory = fs::is_directory(out.path, ec);
  if (!out.is_directory && is_directory)
    throw InputError(where, "is a directory; give a file name");
  if (out.is_directory && (!is_directory || !out.replaceable(out.path)))
    throw InputError(
        where, "exists and is not " + out.kind + "; refusing to replace it, even with --force");
  if (!force_) throw InputError(where, "exists; give --force to replace it");
}

void OutputGuard::check() const {
  for (std::size_t k = 0; k < outputs_.size(); ++k) {
    const Output& out = outputs_[k];
    checkName(out.path, out.option);
    checkRelations(out, k);
    checkExisting(out);
    checkWritable(out.path, out.option);
  }
  if (!force_)
    for (const Output& out : outputs_) refuseToReplace(out.path, out.option);
}

CLI::Validator outputPath() {
  return CLI::Validator(
      [](std::string& value) { return value.empty() ? "is empty: give a path" : std::string(); },
      "");
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

}  // namespace slamprep::app
