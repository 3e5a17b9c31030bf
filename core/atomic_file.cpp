#include "core/atomic_file.hpp"

#include <unistd.h>

#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace slamprep {

void writeFileAtomic(const std::filesystem::path& file, const std::string& text) {
  std::error_code ec;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
  const auto tmp = file.string() + ".partial-" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) {
      std::filesystem::remove(tmp, ec);
      throw InputError(file.string(), "cannot write file");
    }
  }
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw InputError(file.string(), "cannot rename the finished file into place");
  }
}

std::string readFile(const std::filesystem::path& file) {
  std::error_code ec;  // a device or FIFO (/dev/zero) would be read forever
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec))
    throw InputError(file.string(), "not a regular file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "cannot open file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace slamprep
