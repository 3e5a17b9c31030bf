#include "slamprep/core/atomic_file.hpp"

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "slamprep/core/error.hpp"
#include "slamprep/core/partial_cleanup.hpp"
#include "slamprep/core/paths.hpp"

namespace slamprep {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kNameMax = 255;  // NAME_MAX of every Linux filesystem slamprep writes

// Resolved target -> the option that named it; read by every rename, written by the guard.
struct Protected {
  std::mutex mutex;
  std::map<std::string, std::string> options;
};
Protected& protectedOutputs() {
  static Protected registry;
  return registry;
}

[[noreturn]] void renameFailed(const fs::path& to, int error) {
  throw InputError(to.string(), std::string("cannot rename the finished output into place: ") +
                                    std::strerror(error));
}

// rename(2) that fails with EEXIST instead of replacing. Where the filesystem lacks
// RENAME_NOREPLACE, a file is linked (link(2) never replaces) and a folder checked just before.
int renameNoReplace(const fs::path& from, const fs::path& to) {
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) return 0;
  if (errno != EINVAL && errno != ENOSYS) return -1;
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(from, ec))) {
    if (::link(from.c_str(), to.c_str()) != 0) return -1;
    return ::unlink(from.c_str());
  }
  if (fs::exists(fs::symlink_status(to, ec))) {
    errno = EEXIST;
    return -1;
  }
  return ::rename(from.c_str(), to.c_str());
}

}  // namespace

fs::path partialSibling(const fs::path& target, const std::string& tag) {
  fs::path clean = target.lexically_normal();
  if (!clean.has_filename()) clean = clean.parent_path();
  const std::string suffix = "." + tag + "-" + std::to_string(::getpid());
  std::string name = clean.filename().string();
  if (name.size() + suffix.size() > kNameMax && suffix.size() < kNameMax)
    name.resize(kNameMax - suffix.size());
  return clean.parent_path() / (name + suffix);
}

void refuseToReplace(const fs::path& target, const std::string& option) {
  Protected& p = protectedOutputs();
  const std::lock_guard lock(p.mutex);
  p.options[resolvedPath(target).string()] = option;
}

bool mayReplace(const fs::path& target) {
  Protected& p = protectedOutputs();
  const std::lock_guard lock(p.mutex);
  return p.options.empty() || !p.options.contains(resolvedPath(target).string());
}

bool renameIfAbsent(const fs::path& from, const fs::path& to) {
  if (renameNoReplace(from, to) == 0) return true;
  if (errno != EEXIST && errno != ENOTEMPTY) renameFailed(to, errno);
  return false;
}

void renameIntoPlace(const fs::path& from, const fs::path& to) {
  if (mayReplace(to)) {
    if (::rename(from.c_str(), to.c_str()) != 0) renameFailed(to, errno);
    return;
  }
  if (renameIfAbsent(from, to)) return;
  std::string option;
  {
    Protected& p = protectedOutputs();
    const std::lock_guard lock(p.mutex);
    option = p.options[resolvedPath(to).string()];
  }
  throw InputError(option + " " + to.string(),
                   "appeared while this command ran (another run writing it?); not replaced "
                   "without --force: this run's output is discarded");
}

void writeFileAtomic(const fs::path& file, const std::string& text) {
  std::error_code ec;
  if (file.has_parent_path()) fs::create_directories(file.parent_path(), ec);
  const fs::path tmp = partialSibling(file);
  const PartialInFlight in_flight(tmp);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) {
      fs::remove(tmp, ec);
      throw InputError(file.string(), "cannot write file");
    }
  }
  try {
    renameIntoPlace(tmp, file);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
}

std::string readFile(const fs::path& file) {
  std::error_code ec;  // a device or FIFO (/dev/zero) would be read forever
  if (fs::exists(file, ec) && !fs::is_regular_file(file, ec))
    throw InputError(file.string(), "not a regular file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "cannot open file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace slamprep
