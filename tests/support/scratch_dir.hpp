#pragma once
// A test's own scratch folder under the system temp dir: created empty, unique to the process and
// the object (ctest runs tests in parallel processes), removed with its contents when it goes out
// of scope, so a failed assertion leaves nothing behind either.

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>

namespace slamprep::test {

class ScratchDir {
 public:
  /// Creates <temp>/slamprep_<name>_<pid>_<n>, skipping n already taken (by a stale folder).
  explicit ScratchDir(std::string_view name) {
    static std::atomic<unsigned> counter{0};
    const std::string stem =
        "slamprep_" + std::string(name) + "_" + std::to_string(::getpid()) + "_";
    do {
      path_ = std::filesystem::temp_directory_path() / (stem + std::to_string(counter++));
    } while (!std::filesystem::create_directory(path_));
  }
  ~ScratchDir() {
    std::error_code ignored;  // a destructor must not throw; a leftover is not a test failure
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const noexcept { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& child) const {
    return path_ / child;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace slamprep::test
